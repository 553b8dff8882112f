"""The exceptions of kreisel. Every error kreisel raises derives from :class:`KreiselError`."""


class KreiselError(Exception):
    """Base class of every error kreisel raises.

    Examples
    --------
    >>> from kreisel import KreiselError, LagrangeTop
    >>> try:
    ...     LagrangeTop(I1=0.0125, I3=0.005, m=-0.5, l=0.1)
    ... except KreiselError as e:
    ...     print(type(e).__name__)
    ParameterError
    """


class ParameterError(KreiselError, ValueError):
    """A parameter or argument has a value outside what is allowed.

    The message names the parameter, the value, and what is allowed.

    Examples
    --------
    >>> from kreisel import LagrangeTop, ParameterError
    >>> try:
    ...     LagrangeTop(I1=0.0125, I3=0.005, m=-0.5, l=0.1)
    ... except ParameterError as e:
    ...     print(e)
    m = -0.5 is not allowed: it must be a finite number > 0 within [1e-100, 1e+100]
    >>> issubclass(ParameterError, ValueError)
    True
    """


class ParameterTypeError(ParameterError, TypeError):
    """An argument of the wrong type (a number where a state is needed, ...): a
    :class:`ParameterError` that is also a ``TypeError``. The message names the argument."""


class NumericalError(KreiselError, RuntimeError):
    """A computation could not deliver a trustworthy result.

    Examples
    --------
    >>> from kreisel import KreiselError, NumericalError
    >>> issubclass(NumericalError, KreiselError), issubclass(NumericalError, RuntimeError)
    (True, True)
    """


class FitWarning(UserWarning):
    """A fit's result needs care: the data cannot tell some free names apart (the warning
    names the combinations that are identifiable), or the solver did not converge.

    Examples
    --------
    >>> from kreisel import FitWarning
    >>> issubclass(FitWarning, UserWarning)
    True
    """
