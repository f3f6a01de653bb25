"""Per-stage progress lines on stderr."""

import io

import pytest

from oacdsl.progress import Progress, format_duration


class Tty(io.StringIO):
    def isatty(self):
        return True


def clock(*times):
    it = iter(times)
    return lambda: next(it)


def test_plain_lines_when_not_a_terminal():
    out = io.StringIO()
    p = Progress(["segment", "match", "compose"], stream=out, clock=clock(0.0, 0.4, 1.0, 13.5),
                 cpu_clock=clock(5.0, 5.25, 5.5, 13.0))
    with p.stage("segment"):
        p.note("reading")  # notes only show on a terminal
    with p.stage("match"):
        pass
    p.skip("compose", "nothing matched")
    assert out.getvalue().splitlines() == [
        "[1/3] segment done in 0.40 s",
        "[2/3] match done in 12.5 s",
        "[3/3] compose skipped: nothing matched",
    ]
    assert p.records() == [
        {"name": "segment", "status": "ok", "duration_s": 0.4, "cpu_s": 0.25, "detail": None},
        {"name": "match", "status": "ok", "duration_s": 12.5, "cpu_s": 7.5, "detail": None},
        {"name": "compose", "status": "skipped", "duration_s": None, "cpu_s": None,
         "detail": "nothing matched"},
    ]
    assert p.elapsed_s == pytest.approx(12.9)


def test_terminal_updates_the_stage_line_in_place():
    out = Tty()
    p = Progress(2, stream=out, clock=clock(0.0, 2.0))
    with p.stage("execute"):
        p.note("step 3/8: pour")
    text = out.getvalue()
    assert text.startswith("[1/2] execute …")
    assert "\r\x1b[K[1/2] execute … step 3/8: pour" in text
    assert text.endswith("\r\x1b[K[1/2] execute done in 2.0 s\n")


def test_quiet_prints_nothing_but_records():
    out = Tty()
    p = Progress(1, stream=out, quiet=True, clock=clock(0.0, 1.0))
    with p.stage("segment"):
        p.note("x")
    assert out.getvalue() == "" and p.records()[0]["status"] == "ok"


def test_a_failing_stage_is_reported_and_the_error_propagates():
    out = io.StringIO()
    p = Progress(["segment"], stream=out, clock=clock(0.0, 0.25), cpu_clock=clock(1.0, 1.125))
    with pytest.raises(ValueError, match="bad marker"), p.stage("segment"):
        raise ValueError("bad marker\nmore detail")
    assert out.getvalue() == "[1/1] segment failed after 0.25 s\n"
    assert p.records() == [
        {"name": "segment", "status": "failed", "duration_s": 0.25, "cpu_s": 0.125,
         "detail": "bad marker"}
    ]


def test_counter_grows_past_the_plan_and_nesting_is_refused():
    out = io.StringIO()
    p = Progress(1, stream=out, clock=clock(0, 0, 0, 0))
    with p.stage("a"):
        with pytest.raises(RuntimeError, match="inside stage 'a'"), p.stage("b"):
            pass
    with p.stage("c"):
        pass
    assert out.getvalue().splitlines()[-1].startswith("[2/2] c done")


def test_a_closed_stream_does_not_break_the_work():
    out = io.StringIO()
    out.close()
    p = Progress(1, stream=out, clock=clock(0, 1))
    with p.stage("a"):
        pass
    assert p.records()[0]["status"] == "ok"


@pytest.mark.parametrize(
    "s, text", [(0.0421, "0.04 s"), (3.21, "3.2 s"), (42.0, "42.0 s"), (125.4, "2 min 05 s")]
)
def test_format_duration(s, text):
    assert format_duration(s) == text
