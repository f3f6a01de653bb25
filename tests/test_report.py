"""The report page: one self-contained HTML page and result.json, from one result dict."""

import copy
import json
import re
import shutil

import pytest
from report_fixture import INSTANCES, STEPS, dough_result, keyframe_relations

from oacdsl.errors import InputError, ResultError
from oacdsl.report import render_html, validate_result, write_report
from oacdsl.report.demonstration import steps_of_sub_actions
from oacdsl.report.execution import compare_step
from oacdsl.report.figures import marker_snapshot_png, relation_timeline_png, world_state_png
from oacdsl.report.schema import RunStepDoc
from oacdsl.verify import verify
from oacdsl.world import WorldState

PNG = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def base(tmp_path_factory):
    out = tmp_path_factory.mktemp("base")
    return out, dough_result(out)


@pytest.fixture
def work(base, tmp_path):
    """A fresh output folder with the pictures, and a deep copy of the result to modify."""
    src, result = base
    shutil.copytree(src / "figures", tmp_path / "figures")
    return tmp_path, copy.deepcopy(result)


def img_sources(page):
    return re.findall(r'<img [^>]*src="([^"]*)"', page)


def test_report_is_one_self_contained_page_and_result_json_holds_the_data(work):
    out, result = work
    report = write_report(result, out)
    assert report.html == out / "report.html" and report.json == out / "result.json"
    assert report.warnings == []
    page = report.html.read_text(encoding="utf-8")
    assert page.startswith("<!DOCTYPE html>") and "<style>" in page
    assert "<script" not in page.lower()
    assert not re.search(r'(src|href)="(https?:)?//', page)  # no network
    sources = img_sources(page)
    # Fig. 3 plot + timeline + per keyframe (snapshot, graph, robot) + a frame per executed step.
    assert len(sources) == 2 + 9 * 3 + 8
    assert all(s.startswith("data:image/png;base64,") for s in sources)
    for section in ("demonstration", "keyframes", "composed", "execution", "verification", "reliability"):
        assert f'<section id="{section}">' in page
    assert json.loads(report.json.read_text(encoding="utf-8")) == result
    assert "✔ Reproduced and verified" in page
    # The composed OAC's text, highlighted and escaped; the provenance table.
    assert '<span class="kw">effect</span>' in page and "l1 <span class=\"op\">&lt;-&gt;</span> b" in page
    assert "step 8: <span class=mono>mix(h=right_hand, m=mixer, b=orange_bowl)</span>" in page
    # Fig. 4 rows: the chosen OAC with its constraints and the runner-up.
    assert "pour(h=left_hand, c=red_cup, l=liquid_one, b=orange_bowl)" in page
    assert "Also matched (1):" in page and "wipe(h=right_hand, s=mixer, t=orange_bowl)" in page
    assert "19 / 20" in page
    assert "verified: the robot made the demonstration&#x27;s 8 world-state changes" in page
    assert not [p for p in out.iterdir() if p.name.startswith(".")]  # no temporary files left


def test_the_page_is_rendered_from_result_json_alone(work):
    out, result = work
    write_report(result, out)
    again, _ = render_html(json.loads((out / "result.json").read_text(encoding="utf-8")), out)
    assert again == (out / "report.html").read_text(encoding="utf-8")


def test_all_text_is_escaped(work):
    out, result = work
    evil = '<script>alert("x")</script>'
    result["verdict"]["summary"] = evil
    result["demonstration"]["recording"] = f"dir/{evil}.c3d"
    result["run"]["steps"][1]["error"] = evil
    result["run"]["steps"][1]["binding"]["h"] = evil
    result["compose"]["text"] += f"# {evil}\n"
    result["match"]["sub_actions"][0]["matches"][0]["note"] = evil
    result["stages"][0]["detail"] = evil
    result["reliability"]["oacs"][0]["last_failure"] = evil
    page = write_report(result, out).html.read_text(encoding="utf-8")
    assert "<script" not in page
    assert page.count("&lt;script&gt;alert(&quot;x&quot;)&lt;/script&gt;") >= 8


def failing_result(result):
    """The pour of liquid one spills: the liquid still touches the cup; the robot skips a step."""
    result["verdict"] = {"success": False, "summary": "pour(left_hand) spilled 9 of 20 balls",
                         "failed_stage": "execute"}
    step = result["run"]["steps"][1]
    step["success"] = False
    step["error"] = "only 11 of 20 balls reached the bowl"
    step["observed"] = [["green_cup", "liquid_two"], ["left_hand", "red_cup"], ["liquid_one", "red_cup"],
                        ["mixer", "orange_bowl"]]
    result["run"]["success"] = False
    result["stages"][3].update(status="failed", detail="pour failed")
    demo = [WorldState.of(INSTANCES, r) for r in keyframe_relations()]
    robot = [demo[0]]
    for i, (_, _, added, removed, _) in enumerate(STEPS):
        if i != 5:  # never sets the green cup down
            robot.append(robot[-1].with_changes(added, removed))
    result["verification"] = verify(demo, robot).to_json()
    return result


def test_failures_and_mismatches_are_highlighted(work):
    out, result = work
    page = write_report(failing_result(result), out).html.read_text(encoding="utf-8")
    assert "✘ Not reproduced — failed at execute" in page
    assert "only 11 of 20 balls reached the bowl" in page
    assert "predicted, not observed" in page and "predicted to end, still holds" in page
    assert "new, not predicted" in page  # mixer touches the bowl before the mix
    assert '<tr class="op-missing">' in page and "not verified: edit distance 1" in page
    assert '<div class="verdict fail">' in page


def test_missing_pictures_become_placeholders_with_warnings(work):
    out, result = work
    (out / "figures" / "robot_3.png").unlink()
    result["segment"]["plot"] = "figures/plot.svgz"
    report = write_report(result, out)
    page = report.html.read_text(encoding="utf-8")
    assert len(report.warnings) == 3  # robot_3 appears in Fig. 4 and in the execution table
    assert "picture unavailable: figures/robot_3.png" in page
    assert any("not an image type" in w for w in report.warnings)


def test_sections_of_stages_that_did_not_run_say_so(tmp_path):
    result = {
        "demonstration": {"recording": "x.c3d"},
        "verdict": {"success": False, "summary": "no sub-action matched", "failed_stage": "match"},
        "stages": [{"name": "segment", "status": "ok", "duration_s": 0.2},
                   {"name": "match", "status": "failed", "duration_s": 0.1, "detail": "sub-action 2: no OAC"},
                   {"name": "compose", "status": "skipped"}],
        "segment": {"recording": "x.c3d", "rate_hz": 100.0, "frames": 200, "instances": ["a", "b"],
                    "keyframes": [{"frame": 0, "time_s": 0.0, "relations": []},
                                  {"frame": 120, "time_s": 1.2, "relations": [["a", "b"]]}]},
    }
    report = write_report(result, tmp_path)
    page = report.html.read_text(encoding="utf-8")
    assert json.loads(report.json.read_text())["schema_version"] == 1
    assert "The composed OAC is not available." in page
    assert "The robot&#x27;s execution is not available." in page
    assert "not matched (matching did not run)" in page
    assert "Reproduction of x.c3d" in page and "No recorded runs." in page


def test_an_unmatched_sub_action_shows_its_explanation(work):
    out, result = work
    sub = result["match"]["sub_actions"][2]
    sub["chosen"], sub["matches"] = None, []
    sub["explanation"] = "closest: place(h=left_hand, o=red_cup): effect left_hand <-> nothing fails after"
    page = write_report(result, out).html.read_text(encoding="utf-8")
    assert "no OAC matched" in page and "effect left_hand &lt;-&gt; nothing fails after" in page


@pytest.mark.parametrize(
    "change, where",
    [
        (lambda r: r["match"]["sub_actions"][3].update(chosen="first"), "match.sub_actions.3.chosen"),
        (lambda r: r["verdict"].pop("success"), "verdict.success"),
        (lambda r: r["run"]["steps"][0].update(observed=[["a"]]), "run.steps.0.observed.0.1"),
        (lambda r: r["stages"][0].update(status="done"), "stages.0.status"),
        # impossible values: out of range, not finite, indices past their lists
        (lambda r: r["verification"].update(fidelity=2.5), "verification.fidelity"),
        (lambda r: r["match"]["sub_actions"][0].update(chosen=99), "match.sub_actions.0"),
        (lambda r: r["segment"]["keyframes"][1].update(frame=-3), "segment.keyframes.1.frame"),
        (lambda r: r["segment"].update(rate_hz=float("nan")), "segment.rate_hz"),
        (lambda r: r["segment"].update(rate_hz=float("inf")), "segment.rate_hz"),
        (lambda r: r["run"]["steps"][0].update(duration_s=-1.0), "run.steps.0.duration_s"),
        (lambda r: r["reliability"]["oacs"][0].update(successes=10**6), "(top)"),
        (lambda r: r["reliability"]["oacs"][0].update(rate=1.5), "reliability.oacs.0.rate"),
        (lambda r: r["verification"]["alignment"][0].update(robot=500), "verification"),
        (lambda r: r["compose"]["provenance"][0].update(keyframe=77), "(top)"),
        (lambda r: r["match"]["sub_actions"][0].update(step=40), "(top)"),
    ],
)
def test_a_result_that_does_not_fit_the_schema_is_a_one_line_error(base, change, where):
    result = copy.deepcopy(base[1])
    change(result)
    with pytest.raises(ResultError) as err:
        validate_result(result, source="result.json")
    assert str(err.value).startswith(f"result.json: {where}: ") and "\n" not in str(err.value)
    assert err.value.exit_code == 1


@pytest.mark.parametrize(
    "video, linked",
    [
        ("javascript:alert(1)", False),
        (" JavaScript:alert(1)", False),
        ("java\tscript:alert(1)", False),
        ("data:text/html,<script>alert(1)</script>", False),
        ("vbscript:msgbox", False),
        ("//evil.example/x.mp4", False),
        ("run.mp4", True),
        ("videos/dough run.mp4", True),
        ("https://example.org/dough.mp4", True),
        ("file:///tmp/dough.mp4", True),
    ],
)
def test_a_video_link_is_only_made_for_a_relative_path_or_a_web_or_file_url(work, video, linked):
    out, result = work
    result["run"]["video"] = video
    page, _ = render_html(result, out)
    paragraph = next(line for line in page.split("<p>") if line.startswith("Video:"))
    assert ("<a href=" in paragraph) is linked, paragraph
    assert "<script" not in page


def test_oacc_report_refuses_deep_or_impossible_json_with_one_line(work, capsys):
    from oacdsl.cli import main

    out, result = work
    cases = {
        "deep.json": "[" * 100_000 + "]" * 100_000,
        "deep_field.json": json.dumps({**result, "extra": json.loads("[" * 200 + "]" * 200)}),
        "fidelity.json": json.dumps({**result, "verification": {**result["verification"], "fidelity": 2.5}}),
        "nan.json": json.dumps(result).replace('"rate_hz": 100.0', '"rate_hz": NaN'),
        "list.json": "[1, 2]",
    }
    assert '"rate_hz": NaN' in cases["nan.json"]
    for name, text in cases.items():
        (out / name).write_text(text)
        assert main(["report", str(out / name)]) == 1, name
        err = capsys.readouterr().err
        assert err.startswith(f"oacc: error: {out / name}: ") and err.count("\n") == 1, err
    assert not (out / "report.html").exists()


def test_newer_schema_and_unserialisable_values_are_refused_without_touching_files(work):
    out, result = work
    write_report(result, out)
    before = (out / "report.html").read_bytes()
    with pytest.raises(InputError, match="schema_version 2 is not supported"):
        write_report({**result, "schema_version": 2}, out)
    bad = copy.deepcopy(result)
    bad["run"]["metrics"]["sim_time_s"] = float("nan")
    with pytest.raises(InputError, match="cannot be written as JSON"):
        write_report(bad, out)
    assert (out / "report.html").read_bytes() == before
    assert not [p for p in out.iterdir() if p.name.startswith(".")]


def test_compare_step_marks_true_false_and_unpredicted_relations():
    step = RunStepDoc(oac="pour", binding={}, success=False,
                      predicted=[("liquid_one", "orange_bowl"), ("left_hand", "nothing")],
                      predicted_not=[("liquid_one", "red_cup")],
                      observed=[("liquid_one", "orange_bowl"), ("liquid_one", "red_cup"), ("mixer", "table")])
    rows = compare_step(step, previous=[("liquid_one", "red_cup"), ("cup", "hand")])
    assert rows == [
        (("liquid_one", "orange_bowl"), "ok", "predicted, observed"),
        (("left_hand", "nothing"), "ok", "predicted, observed"),
        (("liquid_one", "red_cup"), "bad", "predicted to end, still holds"),
        (("mixer", "table"), "warn", "new, not predicted"),
        (("cup", "hand"), "warn", "ended, not predicted"),
    ]
    step2 = RunStepDoc(oac="grasp", binding={}, success=False, predicted=[("hand", "nothing")],
                       observed=[("cup", "hand")])
    assert compare_step(step2, None) == [(("hand", "nothing"), "bad", "predicted, not observed")]


def test_sub_actions_are_paired_with_run_steps_by_name_in_order(base):
    result = copy.deepcopy(base[1])
    assert steps_of_sub_actions(validate_result(result)) == list(range(8))
    result["run"]["steps"] = result["run"]["steps"][:2] + result["run"]["steps"][3:]  # place missing
    result["match"]["sub_actions"][4]["step"] = 0  # explicit pairing wins
    paired = steps_of_sub_actions(validate_result(result))
    assert paired[:3] == [0, 1, 4] and paired[4] == 0


def test_figures_are_png_and_show_what_changed(base):
    after, before = [["a", "b"]], [["b", "c"]]
    plain = world_state_png(["a", "b", "c"], after)
    changed = world_state_png(["a", "b", "c"], after, before)
    assert plain.startswith(PNG) and changed.startswith(PNG) and plain != changed
    assert relation_timeline_png([(0.0, []), (1.0, [["a", "b"]])], 2.0).startswith(PNG)
    from report_fixture import synthetic_recording

    rec = synthetic_recording([0.0])
    assert marker_snapshot_png(rec, 0).startswith(PNG)
    with pytest.raises(ValueError, match="outside the recording"):
        marker_snapshot_png(rec, rec.n_frames)


def test_oacc_report_renders_the_page_again_from_result_json(work, capsys):
    from oacdsl.cli import main

    out, result = work
    write_report(result, out)
    (out / "report.html").unlink()
    assert main(["report", str(out / "result.json")]) == 0
    assert capsys.readouterr().out.strip() == str(out / "report.html")
    assert len(img_sources((out / "report.html").read_text(encoding="utf-8"))) == 2 + 9 * 3 + 8
    (out / "bad.json").write_text('{"demonstration": {"recording": "x"}}')
    assert main(["report", str(out / "bad.json")]) == 1
    err = capsys.readouterr().err
    assert err == f"oacc: error: {out / 'bad.json'}: verdict: Field required\n"


def test_oacc_report_through_a_published_folder_writes_into_the_run_and_keeps_the_links(work, capsys):
    from oacdsl.cli import main
    from oacdsl.pipeline.publish import make_staging, publish

    src, result = work
    out = src / "out"
    staging = make_staging(out)
    shutil.copytree(src / "figures", staging / "figures")
    write_report(result, staging)
    publish(staging, out)
    run_folder = (out / "current").resolve()
    (run_folder / "report.html").unlink()
    assert main(["report", str(out / "result.json")]) == 0
    assert capsys.readouterr().out.strip() == str(run_folder / "report.html")
    assert all((out / name).is_symlink() for name in ("report.html", "result.json", "figures"))
    assert len(img_sources((out / "report.html").read_text(encoding="utf-8"))) == 2 + 9 * 3 + 8


def test_an_adaptive_runs_adaptations_are_listed_escaped(work):
    out, result = work
    result["run"]["adaptations"] = [
        {"kind": "skipped", "step": 0,
         "text": "skipped pour(left_hand, red_cup, liquid_one, orange_bowl): <x>"},
        {"kind": "replanned", "step": 2, "text": "replanned after step 2 failed", "plan": ["grasp(a, b)"]},
    ]
    page, _ = render_html(result, out)
    assert "Adapted to the world at execution time" in page
    assert "skipped pour(left_hand, red_cup, liquid_one, orange_bowl): &lt;x&gt;" in page
    assert "→ grasp(a, b)" in page
    del result["run"]["adaptations"]
    assert "Adapted to the world" not in render_html(result, out)[0]
