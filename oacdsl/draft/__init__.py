"""Drafting a ``.oac`` scene from a recording (``oacc draft``): geometry estimated from markers."""

from oacdsl.draft.estimate import ShapeEstimate, estimate_shape, table_height
from oacdsl.draft.scene import Draft, draft_scene

__all__ = ["Draft", "ShapeEstimate", "draft_scene", "estimate_shape", "table_height"]
