"""The one exception type the suite raises for bad input.

Anything the user can get wrong (a missing or corrupt image, NaN/Inf/negative texels, a wrong aspect
ratio, an unknown experiment or environment name) raises :class:`ValidateError` with a one-line
message that names the file or the name and the problem. The CLI prints it without a traceback and
exits with status 2.
"""

from __future__ import annotations


class ValidateError(Exception):
    """Bad input: the message is one line, names the culprit and says what is wrong."""

    def __init__(self, message: str):
        super().__init__(" ".join(str(message).split()))
