"""The exceptions of kreisel. Every error kreisel raises derives from :class:`KreiselError`."""


class KreiselError(Exception):
    """Base class of every error kreisel raises."""


class ParameterError(KreiselError, ValueError):
    """A parameter or argument has a value outside what is allowed.

    The message names the parameter, the value, and what is allowed.
    """


class ParameterTypeError(ParameterError, TypeError):
    """An argument of the wrong type (a number where a state is needed, ...): a
    :class:`ParameterError` that is also a ``TypeError``. The message names the argument."""


class NumericalError(KreiselError, RuntimeError):
    """A computation could not deliver a trustworthy result."""
