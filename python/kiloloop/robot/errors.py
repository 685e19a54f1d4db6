"""RobotFileError, in a module of its own: the file reader and the family modules both raise it,
and the reader calls the families, so neither can hold it without an import circle."""
from ..errors import InputError


class RobotFileError(InputError):
    """A robot file that cannot be used; the message names the file and the key at fault."""
