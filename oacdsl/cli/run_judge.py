"""``oacc run --demonstration``: record the run and judge it as ``oacc verify`` does."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

__all__ = ["RunJudge"]


class RunJudge:
    """With --demonstration: records the robot's virtual markers and the simulation's contacts,
    writes them (--execution) and judges the run as `oacc verify` and `oacc reproduce` do
    (:func:`oacdsl.verify_execution.verify_execution`)."""

    def __init__(self, run: Any) -> None:
        from oacdsl.pipeline.markers import VirtualMarkers
        from oacdsl.runtime.recorder import ContactRecorder

        self.markers = VirtualMarkers(run.world)
        self.contacts = ContactRecorder(self.markers.rate_hz, regrasps=run.controller.regrasps)
        run.controller.add_observer(self.markers)
        run.controller.add_observer(self.contacts)

    def verdict(self, args: argparse.Namespace, library: Any, scene: Any, out: Any,
                any_hands: bool = False) -> int:
        """Write the recording and print the verdict; ``any_hands``: the run exchanged the two
        hands for the whole task (a left-handed demonstration), so the judge may exchange them
        too, as `oacc reproduce` does (else such a run fails the relations where reproduce
        verifies it)."""
        from oacdsl.cli.verify_cmd import format_outcome
        from oacdsl.pipeline.robot import sim_contacts, write_execution
        from oacdsl.segmentation.grouping import apply_scene_groups, group_recording
        from oacdsl.segmentation.params import AasParams
        from oacdsl.segmentation.readers import read_recording
        from oacdsl.verify_execution import verify_execution

        demo, _ = group_recording(read_recording(args.demonstration), None)
        if any(i.markers or i.ignored for i in scene.instances):
            demo = apply_scene_groups(demo, scene)
        params = AasParams()
        recording = self.markers.to_recording("robot (virtual markers)", instances=list(demo.instances))
        contacts = sim_contacts(self.contacts, params)
        written = write_execution(recording, contacts, Path(args.execution))
        outcome = verify_execution(demo, recording, scene=scene, library=library, params=params,
                                   contacts=contacts, any_hands=any_hands)
        print(format_outcome(outcome), file=out)
        print(f"execution: {written[0]} (contacts: {written[-1]})", file=out)
        return 0 if outcome.verified else 1
