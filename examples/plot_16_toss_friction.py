"""
The toss that settles: friction on the floor
=============================================

A coin (the ellipse wall with ε = 99) launched flat, heads up, from a height of 1.2 κ, bounces on a floor with
restitution e = 0.6. Without friction a tenth of the launches end sliding on the floor with their energy above
the barrier of their valley, for ever: undecided. With Coulomb friction μ = 0.3 each impact obeys Stronge's
energetic restitution with Routh's integration of the impulse (it never creates energy), and a coin whose
bounces die out slides, rolls and rocks on the floor until its outcome is decided
(:func:`~coinwall.forward.dynamics.floor.toss_outcomes`, :doc:`/toss`).

The left panels are the basin maps over the launch velocity v0 and spin ω0 (undecided grey); the right panel
follows one toss launched from 2 κ: its energy after each impact and each contact event (rolling without
slipping begins, slipping begins), until its level falls below the barrier of the edge and it can only come to
rest on the face it is on.
"""

import matplotlib.pyplot as plt
import numpy as np

from coinwall import get_case
from coinwall.forward.dynamics.floor import FieldTable, basin_map, field_run
from coinwall.forward.dynamics.floor.field import EVENTS

coin = get_case("coin").wall()
v0, omega0 = np.linspace(0.0, 3.0, 60), np.linspace(0.0, 8.0, 60)
maps = [basin_map(FieldTable(coin, g=1.0, e=0.6, mu=mu), v0, omega0, 1.2) for mu in (0.0, 0.3)]
for result in maps:
    print(result, result.undecided_counts())

table = FieldTable(coin, g=1.0, e=0.6, mu=0.3)
flight = field_run(table, [1.5 * np.pi, 2.0, 5.0, 2.0], 1000)  # launched from 2 κ: it rocks and slides
print(flight)

fig, axes = plt.subplots(1, 3, figsize=(15, 4.4), constrained_layout=True)
palette = {"heads": "#2f6690", "tails": "#c8553d"}
for ax, result in zip(axes[:2], maps):
    colour = np.full(result.outcome.shape + (3,), 0.73)
    for k, name in enumerate(result.names):
        colour[result.outcome == k] = [int(palette[name][j:j + 2], 16) / 255 for j in (1, 3, 5)]
    ax.imshow(colour, origin="lower", extent=(0, 3, 0, 8), aspect="auto", interpolation="nearest")
    decided = 1 - result.fractions()["undecided"]
    ax.set(xlabel="launch velocity v0 (κ/s)", ylabel="spin ω0 (rad/s)",
           title=f"μ = {result.table.mu:g}: {decided:.1%} decided (heads blue, tails red)")

ax = axes[2]
energy = flight.energy
barrier = table.g * (table.landscape.barriers[0] + table.b0)
for kind, marker in ((0, "o"), (4, "^"), (5, "v"), (8, "s")):
    pick = flight.side == kind
    ax.plot(flight.time[pick], energy[pick], marker, ms=4, ls="none", label=EVENTS[kind])
ax.step(flight.time, energy, where="post", color="0.6", lw=0.8)
ax.axhline(barrier, color="k", ls="--", lw=0.8, label="the edge's barrier (g · b max)")
ax.set(xlabel="time (s)", ylabel="energy ½(θ̇² + η̇² + ξ̇²) + gη", yscale="log",
       title=f"one toss from 2 κ: {flight.outcome} after {flight.floor_impacts} impacts")
ax.legend(fontsize=8)
