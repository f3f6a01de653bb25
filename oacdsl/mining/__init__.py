"""Mining many recordings on Dask: segment and match each against a library (``oacc mine``).

``from oacdsl.mining import mine`` (or ``oacdsl.mine(...)``): see :func:`oacdsl.mining.engine.mine`
and docs/mining.md. Dask is the optional extra ``scale``.
"""

from oacdsl.mining.engine import MineResult, mine
from oacdsl.mining.summary import summarise
from oacdsl.mining.table import MineTable

__all__ = ["MineResult", "MineTable", "mine", "summarise"]
