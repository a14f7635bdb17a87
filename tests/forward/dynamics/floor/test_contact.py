"""The contact phases with friction against closed forms: a block sliding on its face, a disc rolling, Housner's
rocking block.

References (none shares code with the kernel):

* A block standing on a face and sliding decelerates at μg (the floor carries its weight, friction is μ times
  it): it stops after |ξ̇|/(μg).  It tips instead when the friction's couple is more than its corners can
  carry, μ h > w (h the centre's height, w the half-width; from the balance of the two corners' forces).
The discs are Fourier walls (one compiled kernel serves every Fourier wall).

* A disc (b constant) rolling without slipping moves uniformly, ξ̇ = R θ̇, with its energy kept; a disc whose
  centre of mass is off its centre (b = R + d cos θ) rocks with the period of its energy integral,
  t = ∫ dθ / θ̇(θ), θ̇² = 2(E − g B)/(1 + B² + B'²) (quadrature by scipy).
* An eccentric disc (b = 1 + 0.3 cos θ) sliding with friction comes to rolling when its slip u_t = ξ̇ − Bθ̇
  reaches 0: the time against scipy's DOP853 with event location on the sliding equations of motion as
  docs/toss.md states them (a second integrator and root finder); likewise case:egg's wall lifting off while it
  slides (N = g + B''θ̇² reaches 0) and starting to slip while it rolls (μF_n ∓ F_t reaches 0).
* Housner (Bull. Seismol. Soc. Am. 53, 403 (1963)): a uniform rectangular block (half-width w, half-height h,
  tan α = w/h, R² = w² + h² = 3κ²) rocking on a rigid floor without sliding or bouncing keeps the fraction
  1 − (3/2) sin²α of its angular velocity at each impact (angular momentum about the new corner is kept); about
  a corner it is a pendulum, ½ I_o φ̇² = g R (cos(α − φ₀) − cos(α − φ)) with I_o = 4κ², so the time from
  release at the tilt φ₀ to the impact is the quadrature ∫₀^φ₀ dφ/φ̇, and for a slender block Housner's closed
  form T/4 = cosh⁻¹(1/(1 − φ₀/α))/p, p² = 3g/(4R).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from coinwall.forward import Wall
from coinwall.forward.dynamics.floor.field import EVENTS, FieldTable, field_run

EV = {name: k for k, name in EVENTS.items()}


def _block(alpha, **kwargs):
    """The uniform rectangular block with tan α = w/h in units of κ (w² + h² = 3), and w, h.  (Written with its
    numbers in the pattern of the other tests' rectangles, whose compiled kernel it shares.)"""
    w, h = math.sqrt(3) * math.sin(alpha), math.sqrt(3) * math.cos(alpha)
    return FieldTable(Wall.from_expression(f"{w!r}*abs(cos(t)) + {h!r}*abs(sin(t))"), g=1.0, **kwargs), w, h


@pytest.mark.parametrize("v0, mu", [(2.0, 0.3), (-3.0, 0.1), (0.7, 0.25)])
def test_a_block_sliding_on_its_face_stops_after_v_over_mu_g(v0, mu):
    """Standing on its short face (θ = 3π/2) with ξ̇ = v0, the block slides to rest in |v0|/(μg): the rest record's
    time, to rounding; it ends at rest on that face (also when its energy was above the barrier at the start).  A
    rectangle is a coin in two dimensions: its short faces are its edges."""
    table, w, h = _block(0.4, e=0.5, mu=mu)
    assert mu * h < w  # the corners carry the friction's couple: no tipping
    flight = field_run(table, [1.5 * math.pi, h, 0.0, 0.0, v0], 50)
    assert flight.status == "rest" and flight.outcome == "edge"
    assert flight.side[-1] == EV["face"]
    assert flight.time[-1] == pytest.approx(abs(v0) / (mu * table.g), rel=1e-13)
    assert flight.v_xi[-1] == 0.0 and flight.floor_impacts == 0


def test_a_block_sliding_with_much_friction_tips_over_its_corner():
    """μ h > w: the friction's couple tips the block onto its front corner at once (the face record is followed by
    motion on a corner, not by rest)."""
    table, w, h = _block(0.3, e=0.5, mu=0.9, settle=False)
    assert 0.9 * h > w
    flight = field_run(table, [1.5 * math.pi, h, 0.0, 0.0, 2.0], 6)
    face = np.flatnonzero(flight.side == EV["face"])
    assert face.size == 1 and flight.time[face[0]] == 0.0 and flight.status != "rest"
    assert flight.theta[-1] > 1.5 * math.pi  # tipped forward (θ grows onto the corner at +w)


def test_a_disc_rolling_without_slipping_keeps_its_energy():
    """b = 1.3: rolling at θ̇ = 2 it turns uniformly, ξ̇ = R θ̇, and its energy stays at its start value until the
    kernel stops it after a whole turn as rolling for ever (no event can come: status 'rolls')."""
    R, w0 = 1.3, 2.0
    table = FieldTable(Wall.from_fourier(R), g=1.0, e=0.5, mu=0.4, settle=False)
    start = [0.2, R, w0, 0.0, R * w0]
    flight = field_run(table, start, 10)
    assert flight.status == "rolls" and len(flight) == 1
    assert flight.theta[-1] - 0.2 == pytest.approx(w0 * flight.time[-1], rel=1e-12)
    assert flight.theta[-1] - 0.2 >= 2 * math.pi
    assert flight.v_xi[-1] == pytest.approx(R * flight.v_theta[-1], rel=1e-14)
    E0 = table.energy(R, w0, 0.0, R * w0)
    assert flight.energy[-1] == pytest.approx(E0, rel=1e-14)


def test_an_eccentric_disc_rocks_with_the_period_of_its_energy_integral():
    """b = 1 + 0.3 cos θ (the centre of mass 0.3 κ off the centre) released at rest at θ0 = 2.2 rocks about θ = π
    without slipping (μ = 2); the kernel stops it as rolling for ever after its third turning point.  Its energy is
    kept, and its time is the energy integral's from the start to its end state (scipy.integrate.quad): 1.5 periods
    and the way back to where it stopped."""
    from scipy.integrate import quad

    g, theta0 = 1.0, 2.2
    other = 2 * math.pi - theta0  # the far turning point: B(other) = B(θ0)
    table = FieldTable(Wall.from_fourier(1.0, cos=[0.3]), g=g, e=0.5, mu=2.0, settle=False)

    def B(x):
        return 1 + 0.3 * math.cos(x)

    def over_sin_half(d):  # d / sin(d/2), 2 at d = 0
        return d / math.sin(d / 2) if d != 0 else 2.0

    def smooth(x):
        # 1/θ̇ times √((x − θ0)(other − x)): θ̇² = 2g(B(θ0) − B(x))/(1 + B² + B'²) and
        # B(θ0) − B(x) = 0.6 sin((x − θ0)/2) sin((other − x)/2), so this is smooth up to both turning points
        m = 1 + B(x) ** 2 + (0.3 * math.sin(x)) ** 2
        return math.sqrt(m / (1.2 * g) * over_sin_half(x - theta0) * over_sin_half(other - x))

    half = quad(smooth, theta0, other, weight="alg", wvar=(-0.5, -0.5))[0]
    flight = field_run(table, [theta0, B(theta0), 0.0, 0.0, 0.0], 10)
    assert flight.status == "rolls" and len(flight) == 1
    end = flight.theta[-1]
    assert flight.energy[-1] == pytest.approx(g * B(theta0), rel=1e-10)  # kept to the steps' errors (1e-12 each)
    back = quad(lambda x: smooth(x) / math.sqrt(x - theta0), end, other, weight="alg", wvar=(0, -0.5))[0]
    assert flight.time[-1] == pytest.approx(3 * half + back, rel=1e-9)


def test_a_sliding_eccentric_disc_stops_slipping_when_scipy_says_in_few_steps():
    """b = 1 + 0.3 cos θ on the floor at θ = 0.5, θ̇ = 0.8, sliding forward at ξ̇ = 2 with μ = 0.3: the slip stops
    (the 'rolling' record) at the time scipy's DOP853 finds for u_t = 0 (rtol = atol = 1e-13) on the sliding
    equations D = 1 + s² − μsB, F_n = (g + B''θ̇²)/D, θ̈ = F_n(μB − s), ξ̈ = −μF_n.  The event is met within
    EVENT_TOL of u's scale (|Δt| ≤ 1e-11 · 3/|u̇| ≈ 4e-11 here) plus the steps' errors: 1e-10 relative.  The
    slip's zero is approached by second-order steps (its rate now and a bound of its second derivative): the
    phase takes at most 70 steps, where first-order steps (a bound of the rate alone) take 101."""
    from scipy.integrate import solve_ivp

    from coinwall.forward.dynamics.floor.fieldkernel import _kernel

    g, mu, d = 1.0, 0.3, 0.3
    table = FieldTable(Wall.from_fourier(1.0, cos=[d]), g=g, e=0.5, mu=mu, settle=False)

    def B(x):
        return 1 + d * math.cos(x)

    def s(x):
        return -d * math.sin(x)

    def rhs(t, y):
        x, w, _vx = y
        fn = (g - d * math.cos(x) * w * w) / (1 + s(x) ** 2 - mu * s(x) * B(x))
        return [w, fn * (mu * B(x) - s(x)), -mu * fn]

    def slip(t, y):
        return y[2] - B(y[0]) * y[1]

    slip.terminal = True
    th0, w0, v0 = 0.5, 0.8, 2.0
    ref = solve_ivp(rhs, (0, 50), [th0, w0, v0], method="DOP853", rtol=1e-13, atol=1e-13, events=slip)
    t_stop = ref.t_events[0][0]
    flight = field_run(table, [th0, B(th0), w0, s(th0) * w0, v0], 3)
    assert flight.side[0] == EV["rolling"]
    assert flight.time[0] == pytest.approx(t_stop, rel=1e-10)
    assert flight.theta[0] == pytest.approx(ref.y_events[0][0][0], rel=1e-10)
    assert flight.v_xi[0] == pytest.approx(ref.y_events[0][0][2], rel=1e-10)
    comp = _kernel(table)
    c, cells, lookup, _wmin, _wmax, tol, valleys, lscale = comp.wall_args(table)
    j = comp.module._cell_of(th0, cells, lookup)
    phase = comp.module._contact(th0, 0, j, w0, v0, 1, table.b0, g, 0.5, mu, 0.0, table.chatter, tol, lscale, c,
                                 cells, valleys, False, 1000)
    assert phase[1] == EV["rolling"] and phase[10] == flight.time[0]
    assert phase[-1] <= 70


EGG = {"cos": [0.05, 0.06], "sin": [0.0, 0.0, 0.04]}  # case:egg's wall as its Fourier series


def _egg(x):
    """B = 1 + b (b0 = 1), B' and B'' of case:egg's Fourier wall at x, by hand (not the kernel's wall code)."""
    b, d1, d2 = 1.0, 0.0, 0.0
    for k, a in enumerate(EGG["cos"], 1):
        b, d1, d2 = b + a * math.cos(k * x), d1 - k * a * math.sin(k * x), d2 - k * k * a * math.cos(k * x)
    for k, a in enumerate(EGG["sin"], 1):
        b, d1, d2 = b + a * math.sin(k * x), d1 + k * a * math.cos(k * x), d2 - k * k * a * math.sin(k * x)
    return b, d1, d2


def _egg_phase(mu, x, w, vx, sig, budget):
    """The kernel's contact phase on case:egg's wall (g = 1, no rolling resistance) from θ = x, θ̇ = w, ξ̇ = vx."""
    from coinwall.forward.dynamics.floor.fieldkernel import _kernel

    table = FieldTable(Wall.from_fourier(1.0, **EGG), g=1.0, e=0.5, mu=mu, settle=False)
    comp = _kernel(table)
    c, cells, lookup, _wmin, _wmax, tol, valleys, lscale = comp.wall_args(table)
    j = comp.module._cell_of(x, cells, lookup)
    return comp.module._contact(x, 0, j, w, vx, sig, table.b0, 1.0, 0.5, mu, 0.0, table.chatter, tol, lscale, c,
                                cells, valleys, False, budget)


def test_a_sliding_egg_lifts_off_when_scipy_says_in_few_steps():
    """case:egg's wall at θ = 4, θ̇ = 2, sliding forward fast (ξ̇ = 8, μ = 0.3): the contact force N = g + B''θ̇²
    falls to 0 and the egg lifts off, at the time and state scipy's DOP853 finds for N = 0 (rtol = atol = 1e-13) on
    the sliding equations D = 1 + s² − μsB, F_n = N/D, θ̈ = F_n(μB − s), ξ̈ = −μF_n.  The phase's last state on the
    floor is read by running it with a budget of exactly its steps (the event is found at the next state's check;
    the lift-off record itself lies after the short free flight that opens the gap).  N's zero is approached by
    second-order steps (its rate now, with the wall's b''', and a bound of its second derivative, with the cell's
    bound of |b''''|): at most 80 steps, where first-order steps take 134."""
    from scipy.integrate import solve_ivp

    mu, x0, w0, v0 = 0.3, 4.0, 2.0, 8.0

    def rhs(t, y):
        B, s, B2 = _egg(y[0])
        fn = (1.0 + B2 * y[1] ** 2) / (1 + s * s - mu * s * B)
        return [y[1], fn * (mu * B - s), -mu * fn]

    def contact_force(t, y):
        return 1.0 + _egg(y[0])[2] * y[1] ** 2

    def slip(t, y):
        return y[2] - _egg(y[0])[0] * y[1]

    contact_force.terminal = slip.terminal = True
    ref = solve_ivp(rhs, (0, 50), [x0, w0, v0], method="DOP853", rtol=1e-13, atol=1e-13, events=[contact_force, slip])
    assert ref.t_events[0].size == 1 and ref.t_events[1].size == 0  # it lifts off, still sliding
    phase = _egg_phase(mu, x0, w0, v0, 1, 1000)
    assert phase[1] == EV["lift-off"] and phase[5] == pytest.approx(ref.y_events[0][0][1], rel=1e-10)
    steps = phase[-1]
    last = _egg_phase(mu, x0, w0, v0, 1, steps)
    assert last[10] == pytest.approx(ref.t_events[0][0], rel=1e-10)
    np.testing.assert_allclose([last[2] + 2 * math.pi * last[3], last[5], last[6]], ref.y_events[0][0], rtol=1e-10)
    assert steps <= 80


def test_a_rolling_egg_starts_slipping_when_scipy_says_in_few_steps():
    """case:egg's wall rolling without slipping from θ = 4, θ̇ = 1.5, μ = 0.3 (no rolling resistance): the friction
    rolling needs, F_t = B'θ̇² + Bθ̈, reaches −μF_n (F_n = g + B'θ̈ + B''θ̇², θ̈ = −B'(g + B''θ̇² + Bθ̇²)/(1 + B² + B'²))
    and the contact slips (the 'slipping' record), at the time and state scipy's DOP853 finds for μF_n ∓ F_t = 0
    (rtol = atol = 1e-13).  The zero is approached by second-order steps (the rates of F_n and F_t now, with the
    wall's b''', and a bound of their second derivatives, with the cell's bound of |b''''|): at most 100 steps,
    where first-order steps take 408."""
    from scipy.integrate import solve_ivp

    mu, x0, w0 = 0.3, 4.0, 1.5

    def forces(y):
        B, s, B2 = _egg(y[0])
        a = (-s * (1.0 + B2 * y[1] ** 2) - B * s * y[1] ** 2) / (1 + B * B + s * s)
        return a, 1.0 + s * a + B2 * y[1] ** 2, s * y[1] ** 2 + B * a

    def slip_forward(t, y):
        _a, fn, ft = forces(y)
        return mu * fn - ft

    def slip_back(t, y):
        _a, fn, ft = forces(y)
        return mu * fn + ft

    slip_forward.terminal = slip_back.terminal = True
    ref = solve_ivp(lambda t, y: [y[1], forces(y)[0]], (0, 50), [x0, w0], method="DOP853", rtol=1e-13, atol=1e-13,
                    events=[slip_forward, slip_back])
    assert ref.t_events[0].size == 0 and ref.t_events[1].size == 1  # F_t reaches −μF_n
    phase = _egg_phase(mu, x0, w0, _egg(x0)[0] * w0, 0, 1000)
    assert phase[1] == EV["slipping"] and phase[7] == 1  # the slip that starts is forward: friction pulls back
    assert phase[10] == pytest.approx(ref.t_events[1][0], rel=1e-10)
    np.testing.assert_allclose([phase[2] + 2 * math.pi * phase[3], phase[5]], ref.y_events[1][0], rtol=1e-10)
    assert phase[-1] <= 100


@pytest.mark.parametrize("alpha", [0.3, 0.15, 0.6])
def test_housners_impact_keeps_one_minus_three_halves_sin2_alpha(alpha):
    """The kernel's corner change (``_corner``) on the block rolling without slipping about its corner (w, −h)
    into its face, e = 0, μ = 2: the angular velocity after it is 1 − (3/2) sin²α times the one before, to
    rounding, and the old corner leaves the floor (the body goes on about the new one)."""
    from coinwall.forward.dynamics.floor.fieldkernel import _kernel

    table, w, h = _block(alpha, e=0.0, mu=2.0, settle=False)
    comp = _kernel(table)
    cells = comp.cells
    jr = int(np.argmin(np.abs(cells[:, 0] - 1.5 * math.pi)))  # the cell right of the kink θ = 3π/2
    assert cells[jr, 0] == pytest.approx(1.5 * math.pi, abs=1e-12)
    omega = -0.37  # rolling back onto the face: on the corner (w, −h), B' = w at the kink, ξ̇ = B θ̇
    vt, ve, _vx, hits, nxt = comp.module._corner(jr - 1, jr, cells[jr, 0], omega, w * omega, h * omega, 0.0, 0.0,
                                                2.0, table.chatter, comp.constants, cells)
    assert hits == 1 and nxt == -1
    assert vt == pytest.approx((1 - 1.5 * math.sin(alpha) ** 2) * omega, rel=1e-14)
    assert ve - (-w) * vt == pytest.approx(0.0, abs=1e-15) and ve - w * vt > 0  # new corner on, old one rising


@pytest.mark.parametrize("alpha, phi0", [(0.3, 0.2), (0.15, 0.1)])
def test_housners_rocking_block(alpha, phi0):
    """Released at rest at the tilt φ0 on its corner, without bouncing (e = 0) or sliding (μ = 2), the block rocks
    and comes to rest on its face.  At each impact the angular velocity keeps the fraction 1 − (3/2) sin²α (the
    velocity before it read from the energy after the impact before, which the integration keeps to 1e-11: 1e-9);
    the time to the first impact is the quadrature of the pendulum about the corner to 1e-9, and between impacts
    twice the quadrature at the amplitude the energy gives."""
    from scipy.integrate import quad

    table, w, h = _block(alpha, e=0.0, mu=2.0, settle=False)
    g, R, Io = table.g, math.sqrt(3), 4.0
    theta0 = 1.5 * math.pi + phi0
    eta0 = w * math.cos(theta0) - h * math.sin(theta0)  # the corner (w, −h) on the floor
    flight = field_run(table, [theta0, eta0, 0.0, 0.0, 0.0], 400)
    corners = np.flatnonzero(flight.side == EV["corner"])
    assert corners.size >= 5 and flight.status == "rest"
    ratio = 1 - 1.5 * math.sin(alpha) ** 2
    energy = [g * eta0] + list(flight.energy[corners])
    for k, i in enumerate(corners[:10]):
        before = math.sqrt(2 * (energy[k] - g * h) / Io)
        assert abs(flight.v_theta[i]) == pytest.approx(ratio * before, rel=1e-9)

    def quarter(amplitude):
        # ∫₀^A dφ/φ̇, φ̇² = (2gR/I_o)(cos(α − A) − cos(α − φ)) = (4gR/I_o) sin(α − (A + φ)/2) sin((A − φ)/2):
        # with the weight (A − φ)^(−1/2) the rest is smooth
        def smooth(p):
            d = amplitude - p
            return math.sqrt(Io / (4 * g * R * math.sin(alpha - (amplitude + p) / 2)) * (d / math.sin(d / 2) if d else 2))
        return quad(smooth, 0, amplitude, weight="alg", wvar=(0, -0.5))[0]

    assert flight.time[corners[0]] == pytest.approx(quarter(phi0), rel=1e-9)
    for k in range(1, 4):
        # the amplitude after impact k: ½ I_o ω² = g R (cos(α − φ) − cos α)
        amplitude = alpha - math.acos(0.5 * Io * flight.v_theta[corners[k - 1]] ** 2 / (g * R) + math.cos(alpha))
        gap = flight.time[corners[k]] - flight.time[corners[k - 1]]
        assert gap == pytest.approx(2 * quarter(amplitude), rel=1e-8)
    # Housner's closed form for the slender block: the linearisation sin x ≈ x (x ≤ α) is off by O(α²)
    p = math.sqrt(3 * g / (4 * R))
    housner = math.acosh(1 / (1 - phi0 / alpha)) / p
    assert flight.time[corners[0]] == pytest.approx(housner, rel=alpha ** 2)


def test_a_block_dropped_flat_on_its_face_bounces_straight_and_rests_on_it():
    """Dropped without spin exactly onto its face (θ = 3π/2, where b has a kink: both corners land together), the
    block's two corners push together through its centre of mass: it bounces straight up and down, each impact
    leaving e times the speed it came with (Stronge's e = Newton's here: no slip), θ̇ = 0 throughout, and it comes
    to rest on that face.  A free fall from the height d above the floor lands at √(2gd) after √(2d/g); the
    bounces then last 2e^k √(2gd)/g: the k-th impact comes at √(2d/g)(1 + 2e(1 − e^(k−1))/(1 − e)), to rounding."""
    table, _w, h = _block(0.4, e=0.5, mu=0.3, settle=False)  # followed past its decision, to rest
    d = 1.0
    flight = field_run(table, [1.5 * math.pi, h + d, 0.0, 0.0, 0.0], 100)
    assert flight.status == "rest" and flight.outcome == "edge"
    assert np.all(flight.v_theta == 0.0) and np.all(flight.theta == flight.theta[0])
    assert flight.theta[0] == pytest.approx(1.5 * math.pi, abs=1e-12)
    impacts = np.flatnonzero(flight.side == EV["floor impact"])
    assert impacts.size >= 3
    v, t0 = math.sqrt(2 * table.g * d), math.sqrt(2 * d / table.g)
    for k, i in enumerate(impacts[:6], start=1):
        assert flight.v_eta[i] == pytest.approx(0.5 ** k * v, rel=1e-12)
        assert flight.time[i] == pytest.approx(t0 * (1 + 2 * 0.5 * (1 - 0.5 ** (k - 1)) / 0.5), rel=1e-12)
