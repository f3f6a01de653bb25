"""Motion-capture recordings and the automatic action segmentation (AAS).

This subpackage depends on numpy and :mod:`oacdsl.world` only, never on the
parser: instance names come from marker groups.

``from oacdsl.segmentation import segment, AasParams`` is the entry point:
``segment(recording, params) -> Segmentation``.
"""

from oacdsl.segmentation.aas import segment
from oacdsl.segmentation.params import AasParams

__all__ = ["AasParams", "segment"]
