"""The main job, ``oacc reproduce``: demonstration → segment → match → compose → execute → verify.

``load_inputs`` checks the demonstration, library and scene (the bundled dough
demonstration when no recording is given); ``reproduce`` runs the stages, records
the run in the run store and writes the report. Each stage is also a function of
its own (:mod:`.analyse`, :mod:`.robot`) returning a small record with its part of
``result.json``. See docs/pipeline.md.
"""

from oacdsl.pipeline.inputs import Inputs, bundled_recording, default_name, load_inputs
from oacdsl.pipeline.run import STAGES, Outcome, reproduce

__all__ = ["STAGES", "Inputs", "Outcome", "bundled_recording", "default_name", "load_inputs", "reproduce"]
