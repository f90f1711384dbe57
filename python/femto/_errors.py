"""femto's result codes as Python exceptions carrying the C library's diagnostic."""
from ._femto import ffi, lib


class FemtoError(Exception):
    """A femto call failed. Carries what the C library said.

    Attributes:
        code: the fmResult value (an int); ``name`` its C name, e.g. ``"fm_errSyntax"``.
        file, line, column: where the problem is (empty and 0 when it has no place).
        message: what was found and what was expected.
        warning: the first warning the call gave, with its place ("" if none).
    """

    def __init__(self, code, message, file="", line=0, column=0, warning=""):
        self.code = int(code)
        self.name = ffi.string(lib.fmResultName(self.code)).decode()
        self.message = message
        self.file = file
        self.line = line
        self.column = column
        self.warning = warning
        super().__init__(self._text())

    def _text(self):
        place = self.file
        if place and self.line:
            place += ":%d" % self.line
            if self.column:
                place += ":%d" % self.column
        text = "%s: %s" % (place, self.message) if place else self.message
        return "%s [%s]" % (text, self.name)


def error_from_diagnostic(code, diag, fallback=""):
    """A FemtoError from an fmDiagnostic (cdata pointer); fallback when it holds no message."""
    message = ffi.string(diag.message).decode(errors="replace") if diag != ffi.NULL else ""
    if not message:
        message = fallback or ffi.string(lib.fmResultMessage(code)).decode()
    if diag == ffi.NULL:
        return FemtoError(code, message)
    return FemtoError(code, message, ffi.string(diag.file).decode(errors="replace"),
                      diag.line, diag.column,
                      ffi.string(diag.warning).decode(errors="replace"))


def check(code, diag=None, what=""):
    """Raise FemtoError unless code is fm_ok; diag (an fmDiagnostic*) supplies the detail."""
    if code != lib.fm_ok:
        raise error_from_diagnostic(code, diag if diag is not None else ffi.NULL,
                                    fallback=what)


def invalid_id(what):
    return FemtoError(lib.fm_errInvalidId, "%s is not valid (destroyed, or its world is)" % what)
