"""An expat reader for MMM XML that refuses DTDs and reads a file in bounded chunks.

Shared by the marker reader (:mod:`.mmm`) and the ``ModelPose`` reader (:mod:`.mmm_pose`).
A document type declaration is refused (an MMM file has none): no entity can be declared,
so neither an entity bomb nor an external entity can be expanded.
"""

from __future__ import annotations

import xml.parsers.expat as expat
from pathlib import Path

from oacdsl.errors import InvalidRecording
from oacdsl.segmentation.readers.limits import open_regular

__all__ = ["SafeXmlReader"]

_CHUNK_BYTES = 1 << 16  # bytes fed to the parser at a time


class SafeXmlReader:
    """Base of expat callback classes: subclasses define ``start``, ``end``, ``characters``."""

    def __init__(self, location: str) -> None:
        self.location = location
        self.expat = expat.ParserCreate()
        self.expat.SetParamEntityParsing(expat.XML_PARAM_ENTITY_PARSING_NEVER)
        self.expat.StartDoctypeDeclHandler = self.refuse_dtd
        self.expat.EntityDeclHandler = self.refuse_dtd
        self.expat.StartElementHandler = self.start
        self.expat.EndElementHandler = self.end
        self.expat.CharacterDataHandler = self.characters

    def start(self, tag: str, attrs: dict[str, str]) -> None:
        raise NotImplementedError

    def end(self, tag: str) -> None:
        raise NotImplementedError

    def characters(self, data: str) -> None:
        raise NotImplementedError

    def fail(self, message: str) -> InvalidRecording:
        return InvalidRecording(f"line {self.expat.CurrentLineNumber}: {message}", location=self.location)

    def refuse_dtd(self, *_: object) -> None:
        raise self.fail("a document type declaration (DTD, entities) is not allowed in an MMM file")

    def feed_file(self, path: Path) -> None:
        """Parse the regular file ``path`` in chunks; malformed XML is one located error."""
        try:
            with open_regular(path) as fh:
                while chunk := fh.read(_CHUNK_BYTES):
                    self.expat.Parse(chunk, False)
                self.expat.Parse(b"", True)
        except expat.ExpatError as err:
            raise InvalidRecording(
                f"not well-formed XML at line {err.lineno}, column {err.offset + 1}"
                f" ({expat.ErrorString(err.code)})",
                location=self.location,
            ) from None
