"""Bounded scalar minimisation without importing ``scipy.optimize``.

The critical offset refines each minimum of b + b'' with Brent's bounded method.  That is
``scipy.optimize.minimize_scalar(method="bounded")``, but importing ``scipy.optimize`` costs
0.3–0.7 s on the project's machine — a third of ``coinwall solve``'s whole run on the built-in
example, where nothing else needs it.  :func:`bounded_minimum` is that method transcribed from scipy's
``_minimize_scalar_bounded`` (scipy 1.17, BSD licence; Brent, *Algorithms for Minimization without
Derivatives*, 1973, ch. 5): the same operations in the same order, hence the same iterates and the same
answer (``tests/inverse/test_speed_paths.py`` holds it to scipy's, bit for bit).
"""

from __future__ import annotations

import math

__all__ = ["bounded_minimum"]

_SQRT_EPS = math.sqrt(2.2e-16)
_GOLDEN = 0.5 * (3.0 - math.sqrt(5.0))


def _sign(value: float) -> float:
    return (value > 0) - (value < 0)


def bounded_minimum(func, lower: float, upper: float, xatol: float = 1e-5, maxiter: int = 500):
    """A local minimum of ``func`` on ``[lower, upper]`` by Brent's bounded method (golden section and
    parabolic steps).

    Parameters
    ----------
    func : callable
        float -> float.
    lower, upper : float
        Finite bounds, ``lower <= upper``.
    xatol : float
        Absolute tolerance in x.
    maxiter : int
        Most evaluations of ``func``.

    Returns
    -------
    x, fx : float
        Where the minimum was found and the value there (``fx`` is NaN-free unless ``func`` gave NaN).
    """
    a, b = float(lower), float(upper)
    fulc = a + _GOLDEN * (b - a)
    nfc, xf = fulc, fulc
    rat = e = 0.0
    x = xf
    fx = func(x)
    num = 1
    ffulc = fnfc = fx
    xm = 0.5 * (a + b)
    tol1 = _SQRT_EPS * abs(xf) + xatol / 3.0
    tol2 = 2.0 * tol1
    while abs(xf - xm) > (tol2 - 0.5 * (b - a)):
        golden = True
        if abs(e) > tol1:  # try a parabolic fit
            golden = False
            r = (xf - nfc) * (fx - ffulc)
            q = (xf - fulc) * (fx - fnfc)
            p = (xf - fulc) * q - (xf - nfc) * r
            q = 2.0 * (q - r)
            if q > 0.0:
                p = -p
            q = abs(q)
            r = e
            e = rat
            if abs(p) < abs(0.5 * q * r) and p > q * (a - xf) and p < q * (b - xf):  # acceptable parabola
                rat = (p + 0.0) / q
                x = xf + rat
                if (x - a) < tol2 or (b - x) < tol2:
                    rat = tol1 * (_sign(xm - xf) + ((xm - xf) == 0))
            else:
                golden = True
        if golden:  # a golden-section step
            e = (a - xf) if xf >= xm else (b - xf)
            rat = _GOLDEN * e
        x = xf + (_sign(rat) + (rat == 0)) * max(abs(rat), tol1)
        fu = func(x)
        num += 1
        if fu <= fx:
            if x >= xf:
                a = xf
            else:
                b = xf
            fulc, ffulc = nfc, fnfc
            nfc, fnfc = xf, fx
            xf, fx = x, fu
        else:
            if x < xf:
                a = x
            else:
                b = x
            if fu <= fnfc or nfc == xf:
                fulc, ffulc = nfc, fnfc
                nfc, fnfc = x, fu
            elif fu <= ffulc or fulc == xf or fulc == nfc:
                fulc, ffulc = x, fu
        xm = 0.5 * (a + b)
        tol1 = _SQRT_EPS * abs(xf) + xatol / 3.0
        tol2 = 2.0 * tol1
        if num >= maxiter:
            break
    return xf, fx
