"""Motion-capture recordings and the automatic action segmentation (AAS).

This subpackage depends on numpy and :mod:`oacdsl.world` only, never on the
parser: instance names come from marker groups.
"""
