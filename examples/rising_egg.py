"""The rising egg: the threshold spin, swept and against the theory
=================================================================

Figure: a hard-boiled egg (kreisel.bodies.egg: a uniform solid prolate spheroid, semi-axes
22.5 and 30 mm) spun about the vertical while lying on its side, 0.05 rad off the horizontal.

Top: the final ``|u| = |cos(theta)|`` after 120 s against the spin, 101 runs under viscous
friction (kreisel.simulate_many), with the steady no-slip theory (the settled ``|u|`` of
kreisel.bodies.egg_settled_inclination, its thresholds solid) and Moffatt and Shimomura's
gyroscopic balance (its settling curve and thresholds dotted): the egg rises above 46.7 rad/s,
not above the balance's 39.6, and settles where the steady motion of its Jellett's integral
is. Below: one run at 56 rad/s under that viscous law (it rises part way and stays) and one
at 90 rad/s under Coulomb-Contensou friction (it stands on its end, then the drilling torque
drains Jellett's integral J and it sinks back): ``|u|``, the energy E with E + dissipated, and J.

    python examples/rising_egg.py [OUT_DIR]

Writes rising_egg.png.
"""

import sys
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import kreisel
from kreisel import bodies

# the output folder: the script's one argument, else kreisel-out/ (also in a notebook)
out = Path(sys.argv[1] if len(sys.argv) == 2 else "kreisel-out")
out.mkdir(parents=True, exist_ok=True)
a, b = 0.0225, 0.03
th = bodies.egg_rising_thresholds(a, b)
viscous = bodies.egg(a, b, friction=kreisel.Viscous(0.3))


def lying(egg, spin):
    return egg.state(theta=np.pi / 2 - 0.05, phi_dot=spin)


spins = np.linspace(30.0, 80.0, 101)
sweep = kreisel.simulate_many(viscous, [lying(viscous, w) for w in spins], 120.0, rtol=1e-8)
fine = np.linspace(30.0, 80.0, 501)
steady = [bodies.egg_settled_inclination(w, a, b) for w in fine]
h = a * np.clip(fine / th.balance_rise, 1.0, None) ** (2 / 3)  # the balance's minimum of E
balance = np.sqrt(np.clip((h * h - a * a) / (b * b - a * a), 0.0, 1.0))

te = np.linspace(0.0, 20.0, 2001)
runs = {
    "viscous 0.3, 56 rad/s": kreisel.simulate(viscous, lying(viscous, 56.0), 20.0, rtol=1e-8,
                                              t_eval=te),
    "Coulomb-Contensou, 90 rad/s": kreisel.simulate(bodies.egg(a, b), lying(viscous, 90.0), 20.0,
                                                    rtol=1e-8, t_eval=te),
}  # fmt: skip

fig, axes = plt.subplots(4, 1, figsize=(8, 11), gridspec_kw={"height_ratios": [1.4, 1, 1, 1]})
ax = axes[0]
ax.plot(spins, np.abs(sweep.final_u), "o", ms=3, color="k", label="simulated, 120 s")
ax.plot(fine, steady, color="C0", label="steady no-slip motion at the initial J")
ax.plot(fine, balance, color="C3", ls=":", label="gyroscopic balance")
for w, colour, ls in [(th.rise, "C0", "-"), (th.stand, "C0", "-"),
                      (th.balance_rise, "C3", ":"), (th.balance_stand, "C3", ":")]:  # fmt: skip
    ax.axvline(w, color=colour, ls=ls, lw=0.8)
ax.set_xlabel("spin about the vertical, lying (rad/s)")
ax.set_ylabel("final |u|")
ax.legend(loc="upper left", fontsize=8)
for (name, run), colour in zip(runs.items(), ["C0", "C2"]):
    axes[1].plot(run.t, np.abs(run.u), color=colour)
    axes[2].plot(run.t, run.energy * 1e3, color=colour)
    axes[2].plot(run.t, (run.energy + run.dissipated) * 1e3, color=colour, ls="--", lw=0.8)
    axes[3].plot(run.t, run.jellett / run.jellett[0], color=colour, label=name)
axes[1].set_ylabel("|u|")
axes[2].set_ylabel("E, E + dissipated (mJ)")
axes[3].set_ylabel("J / J(0)")
axes[3].legend(loc="center left", fontsize=8)
axes[3].set_xlabel("t (s)")
fig.suptitle("the rising egg: sweep of the spin, and two runs")
fig.tight_layout()
fig.savefig(out / "rising_egg.png", dpi=100)
rise = spins[np.argmax(np.abs(sweep.final_u) > 0.01)]
print(f"first spin that rises: {rise:.2f} rad/s (steady theory {th.rise:.2f}, "
      f"balance {th.balance_rise:.2f})")  # fmt: skip
print(f"wrote {out / 'rising_egg.png'}")
