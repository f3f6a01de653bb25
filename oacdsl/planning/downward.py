"""Fast Downward run directly on the task's PDDL (the planner inside the ``up-fast-downward`` wheel).

``oacc pddl``'s two files are written to a temporary folder, translated to Fast Downward's
SAS+ task by its translator (the ``fast-downward.translate`` package the wheel depends on,
called in this process: no interpreter to start) and searched by the wheel's search binary;
the plan file it writes is read back. unified-planning is not in this path: its PDDL reader
and writer (read ``problem.pddl`` with pyparsing, write it again for the planner) took twice
the planner's own time on a 50-instance scene, and its driver starts two interpreters.
The search's exit codes (https://www.fast-downward.org/ExitCodes): 0-3 a plan, 10-12 none
(proven, or the whole search space seen), anything else a
:class:`~oacdsl.errors.PlanningError` with the planner's last line.
"""

from __future__ import annotations

import importlib.util
import io
import subprocess
import threading
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path
from tempfile import TemporaryDirectory

from oacdsl.errors import PlanningError
from oacdsl.planning.pddl import domain_text, problem_text
from oacdsl.planning.task import Task

__all__ = ["LAMA_FIRST", "run", "search_binary"]

#: The satisficing search: the driver's ``lama-first`` alias (unified-planning's default for
#: Fast Downward), as the wheel's ``driver/aliases.py`` writes it.
LAMA_FIRST = (
    "let(hlm, eval_modify_costs(landmark_sum(lm_factory=lm_reasonable_orders_hps(lm_rhw()),pref=false),"
    "cost_type=one),let(hff, eval_modify_costs(ff(),cost_type=one),"
    "lazy_greedy([hff,hlm],preferred=[hff,hlm],cost_type=one,reopen_closed=false)))"
)
_PLAN_CODES = (0, 1, 2, 3)  # a plan (possibly with the memory or time limit hit afterwards)
_NO_PLAN_CODES = (10, 11, 12)  # unsolvable, or no plan in the whole search space
_EXTRA = "planning needs the 'plan' extra (pip install oacdsl[plan])"
#: The translator keeps its options in a module global: one translation at a time.
_TRANSLATING = threading.Lock()


def search_binary() -> Path:
    """The wheel's search binary (PlanningError naming the extra when it is not installed)."""
    spec = importlib.util.find_spec("up_fast_downward")
    folders = list(spec.submodule_search_locations or []) if spec is not None else []
    for folder in folders:
        path = Path(folder) / "downward" / "builds" / "release" / "bin" / "downward"
        if path.is_file():
            return path
    raise PlanningError(f"{_EXTRA}: no up-fast-downward")


def _last_line(text: str) -> str:
    lines = [line.strip() for line in text.splitlines() if line.strip()]
    return lines[-1] if lines else "no output"


def _translate(folder: Path) -> None:
    """``domain.pddl`` and ``problem.pddl`` of ``folder`` → ``output.sas``."""
    try:
        from fast_downward.translate import options
        from fast_downward.translate.main import main as translate
    except ImportError as error:
        raise PlanningError(f"{_EXTRA}: {error}") from None
    args = [str(folder / "domain.pddl"), str(folder / "problem.pddl")]
    args += ["--sas-file", str(folder / "output.sas")]
    log = io.StringIO()
    with _TRANSLATING, redirect_stdout(log), redirect_stderr(log):
        try:
            options.set_options(args)
            translate()
        except SystemExit as error:  # the translator's way to refuse an input
            why = str(error) or _last_line(log.getvalue())
            raise PlanningError(f"fast-downward's translator: {why}") from None
        except Exception as error:
            why = f"{type(error).__name__}: {error}"
            raise PlanningError(f"fast-downward's translator failed: {why}") from None


def run(task: Task, search: str | None = None) -> list[tuple[str, list[str]]] | None:
    """The plan for ``task`` as (PDDL action, PDDL arguments) per step, or None when there is
    none. ``search`` is a search configuration (``astar(blind())``); None: :data:`LAMA_FIRST`."""
    binary = search_binary()
    with TemporaryDirectory(prefix="oacdsl-fd-") as name:
        folder = Path(name)
        (folder / "domain.pddl").write_text(domain_text(task), encoding="utf-8")
        (folder / "problem.pddl").write_text(problem_text(task), encoding="utf-8")
        _translate(folder)
        cmd = [str(binary), "--search", search or LAMA_FIRST, "--internal-plan-file", "plan.txt"]
        try:  # in the temporary folder: nothing is left in the caller's
            with open(folder / "output.sas", "rb") as sas:
                done = subprocess.run(cmd, cwd=folder, stdin=sas, capture_output=True, text=True, check=False)
        except OSError as error:
            raise PlanningError(f"fast-downward could not start: {error}") from None
        if done.returncode in _NO_PLAN_CODES:
            return None
        if done.returncode not in _PLAN_CODES:
            why = _last_line(done.stderr) if done.stderr.strip() else _last_line(done.stdout)
            raise PlanningError(f"fast-downward failed (exit {done.returncode}): {why}")
        plan = folder / "plan.txt"
        if not plan.is_file():
            code = done.returncode
            raise PlanningError(f"fast-downward gave no plan and no proof that none exists (exit {code})")
        text = plan.read_text(encoding="utf-8")
    steps = []
    for line in text.splitlines():
        line = line.strip()
        if line and not line.startswith(";"):
            words = line.strip("()").split()
            steps.append((words[0], words[1:]))
    return steps
