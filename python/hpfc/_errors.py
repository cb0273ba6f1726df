"""hpfc.Error: a libhpfcfile status as a Python exception."""


class Error(Exception):
    """A status the library returned.

    code: the library's pinned number (hpfc.h, HPFC_E_*); name: its C name;
    message: the library's text for it (hpfc_strerror); context: what was
    being done (a path, "locate: point 12", ...).
    """

    def __init__(self, code, name, message, context=""):
        super().__init__(code, name, message, context)
        self.code = code
        self.name = name
        self.message = message
        self.context = context

    def __str__(self):
        where = f"{self.context}: " if self.context else ""
        hint = _HINTS.get(self.code, "")
        return f"{where}{self.message} ({self.name}, code {self.code}){hint}"


# What a user can do about a status, where the library's text cannot say it.
_HINTS = {51: "; File.limits are the caps, File.set_limits() raises or lifts them"}
