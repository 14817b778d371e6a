"""Tolerances: how closely a re-run on another machine must reproduce a quantity.

:class:`Tolerance` is the rule ``|b - a| <= atol + rtol * |a|`` of ``numpy.isclose`` with its
reason; the named instances are the kinds of computation whose last bits another machine
amplifies. Claims, figure data and the arena's methods declare one each; ``make verify`` reads them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from decimal import ROUND_HALF_EVEN, Context, Decimal
from typing import Any

from secest.core.validation import ValidationError

__all__ = [
    "CANCELLATION", "DETERMINISTIC", "LMI_ITERATES", "ROUNDING_RESIDUAL", "SIGN_DRIVEN", "Tolerance",
]

_DOUBLE_DIGITS = 17
"""Significant decimal digits that identify any double (``repr`` never needs more)."""

@dataclass(frozen=True)
class Tolerance:
    """How closely a re-run on another machine must reproduce a quantity.

    A fresh value ``b`` reproduces the committed ``a`` when
    ``|b - a| <= atol + rtol * |a|`` (elementwise), the rule of ``numpy.isclose``.

    Parameters
    ----------
    rtol, atol : float
        Relative and absolute tolerance, both >= 0.
    reason : str
        Why this tolerance: what makes the last digits machine-dependent.
    """

    rtol: float
    atol: float
    reason: str

    def __post_init__(self) -> None:
        for name in ("rtol", "atol"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int | float) or not value >= 0:
                raise ValidationError(f"{name} must be a real number >= 0, found {value!r}")
            if not math.isfinite(value):
                raise ValidationError(f"{name} must be finite, found {value!r}")
        if not isinstance(self.reason, str) or not self.reason.strip():
            raise ValidationError("reason must be a non-empty string")

    def as_dict(self) -> dict[str, Any]:
        """The JSON form ``{"rtol": ..., "atol": ..., "reason": ...}``."""
        return {"rtol": float(self.rtol), "atol": float(self.atol), "reason": self.reason}

    def allowed(self, value: float) -> float:
        """The largest difference from ``value`` that still reproduces it: ``atol + rtol*|value|``."""
        return self.atol + self.rtol * abs(float(value))

    def resolution(self, value: float) -> float:
        """The decimal step ``value`` is written with: ``10**(e - 1)``, ``10**e`` the leading digit
        of :meth:`allowed` (so at most a tenth of the tolerance); 0 for a zero tolerance.

        Digits finer than this are rounding noise by the tolerance's own declaration, and
        writing them would only make committed files change from machine to machine.
        """
        exponent = self._exponent(float(value))
        return 0.0 if exponent is None else float(Decimal(1).scaleb(exponent))

    def round(self, value: float) -> float:
        """``value`` rounded (half to even) to a multiple of :meth:`resolution`; -0.0 becomes 0.0.

        Non-finite values, and values whose resolution is finer than a double resolves, are
        returned unchanged.
        """
        v = float(value)
        exponent = self._exponent(v) if math.isfinite(v) else None
        if exponent is None:
            return v + 0.0
        exact = Decimal(v)
        if v != 0.0 and exact.adjusted() - exponent + 1 > _DOUBLE_DIGITS:
            return v + 0.0
        context = Context(prec=2 * _DOUBLE_DIGITS, rounding=ROUND_HALF_EVEN)
        return float(exact.quantize(Decimal(1).scaleb(exponent), context=context)) + 0.0

    def _exponent(self, value: float) -> int | None:
        width = self.allowed(value)
        if width == 0.0 or not math.isfinite(width):
            return None
        return Decimal(width).adjusted() - 1


DETERMINISTIC = Tolerance(
    rtol=1e-9,
    atol=1e-12,
    reason="deterministic floating point: another CPU or BLAS build may reorder sums "
    "and change the last bits",
)
"""Default tolerance of a claim and of figure data: deterministic linear algebra."""

# Named tolerances for the kinds of computation whose last bits another machine amplifies.
# Each was chosen above what re-runs under other BLAS kernels / CPU features measured (the site's
# "Reproducibility"); a notebook declares its own where none of these fits.
ROUNDING_RESIDUAL = Tolerance(
    rtol=1e-9,
    atol=1e-11,
    reason="residual of an identity exact in exact arithmetic (a KKT condition, two formulas or "
    "implementations of one quantity): its value is rounding noise of order n*eps*|operands| "
    "(up to 4e-13 here), which another CPU replaces by other noise of that order",
)
CANCELLATION = Tolerance(
    rtol=1e-6,
    atol=1e-12,
    reason="a small difference of two computed quantities of size ~1 (e.g. an attacked minus an "
    "attack-free estimate): cancellation leaves it a relative precision of eps*|operands|/difference "
    "(6.8e-8 measured on ding2020's smallest leaks, 1.5e-6, under other BLAS kernels)",
)
SIGN_DRIVEN = Tolerance(
    rtol=1e-3,
    atol=5e-3,
    reason="sign-driven (Filippov) dynamics on a fixed step dt: a last-bit difference flips a sgn "
    "at another step and trajectories chatter apart by O(kappa*dt) per coordinate (lee2020: "
    "kappa*dt = 5e-4, 1.7e-3 measured on theta-sums under other BLAS kernels); observer gains "
    "placed at clustered poles differ by ~4e-5 relative",
)
LMI_ITERATES = Tolerance(
    rtol=1e-3,
    atol=1e-3,
    reason="interior-point LMI solves stop at an iterate within their 1e-8 gap tolerance of a flat "
    "optimum: gains and ellipsoids are fixed only to ~1e-5 of their size and the recursion carries "
    "that over the horizon (ma2021: up to 1.4e-4 on estimates under other BLAS kernels)",
)
