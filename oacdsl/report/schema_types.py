"""The building blocks of the ``result.json`` schema: the value types (pairs, images, counts,
fractions, seconds) and the base of every part, open to extra keys but refusing non-finite
numbers (see :mod:`oacdsl.report.schema`)."""

from __future__ import annotations

from typing import Annotated

from pydantic import BaseModel, ConfigDict, Field

__all__ = ["Count", "Doc", "Fraction", "Image", "Pair", "Seconds", "index_ok"]

Pair = tuple[str, str]
Image = str | None
#: A count or an index: a whole number ≥ 0.
Count = Annotated[int, Field(ge=0)]
#: A share: a number in [0, 1].
Fraction = Annotated[float, Field(ge=0.0, le=1.0)]
#: A duration or a time stamp, seconds ≥ 0.
Seconds = Annotated[float, Field(ge=0.0)]


class Doc(BaseModel):
    """The base of every document model: extra fields allowed, numbers finite."""

    # numbers must be finite: JSON's NaN and Infinity (which Python reads) are refused
    model_config = ConfigDict(extra="allow", allow_inf_nan=False)


def index_ok(index: int | None, size: int, what: str) -> None:
    """``index`` (None: none) is a position in a list of ``size`` (a ValueError naming ``what``)."""
    if index is not None and not 0 <= index < size:
        raise ValueError(f"{what} {index} is out of range (there are {size})")
