"""oacdsl: reproduce a demonstrated manipulation task on a humanoid robot.

Motion capture → automatic action segmentation → matching against a library of
Object-Action Complexes written in the ``.oac`` language → composition of a new
OAC → execution on ARMAR-III in MuJoCo → verification. See README.md.
"""

from oacdsl.errors import OacError

__version__ = "0.1.0"

__all__ = ["OacError", "__version__"]
