"""The OAC's success measure: a store of run outcomes and the reliability it measures.

Krüger's Object-Action Complex is (execution, prediction, success measure); the
paper implements the first two. :class:`RunStore` keeps every execution's outcome
per OAC in an embedded SQLite database; :func:`summarise` turns them into success
rates with Wilson intervals (``oacc stats``).
"""

from oacdsl.stats.paths import ENV_VAR, default_db_path, resolve_db_path
from oacdsl.stats.reliability import Reliability, summarise, wilson_interval
from oacdsl.stats.store import (
    APPLICATION_ID,
    SCHEMA_VERSION,
    Outcome,
    RunStore,
)
from oacdsl.stats.writable import ensure_writable

__all__ = [
    "APPLICATION_ID",
    "ENV_VAR",
    "SCHEMA_VERSION",
    "Outcome",
    "Reliability",
    "RunStore",
    "default_db_path",
    "ensure_writable",
    "resolve_db_path",
    "summarise",
    "wilson_interval",
]
