"""Poinsot's construction of the free body ("Poinsot" scene).

The torque-free body of `app.kit.rigid.torque_free` (the Free body scene's simulation, sliders,
presets format, ghost), with the geometry of `physics.poinsot` drawn around it, in ω units
(1 rad/s = `scale` scene units):

* **Poinsot's ellipsoid** ω · I ω = 2T (semi-axes sqrt(2T/I_k)), centred on the fixed point and
  fixed in the body: a child of the body's frame, so it turns with the body at no cost per frame.
  The **polhode** (the path of ω on it) is drawn on it, also in the body frame.
* The **invariable plane** n · x = 2T/|L| (n = L/|L|, fixed in space), on which the ellipsoid
  rolls without slipping; the contact point is ω itself (the orange ω arrow ends there), and
  its path on the plane is the **herpolhode** (the last HERPOLHODE_SECONDS of simulated time).
  The two dashed circles on the plane are the herpolhode's radii ρ_min, ρ_max.
* Beside it (left), **body angular-momentum space**: the sphere |L| = const and the energy ellipsoid
  L · I⁻¹ L = 2T meet along the current polhode (magenta, with the current L_b as a dot), drawn
  in a family of polhodes of other energies (grey: around the largest and the smallest axis)
  and the separatrix through ±|L| e_y′ (red, for I1 < I2 < I3).  The "Energy" slider moves the
  motion to another energy at the same |L| and the same L in space (across the separatrix).

Readouts: T, |L|, the flip period 2K(m)/λ of the current motion (ω_q, the intermediate axis'
component, changes sign every flip period: half the polhode period) and the time of the next
flip, from the closed form (`physics.poinsot`).  Nodes are built once; a new run sets their
scale, points and pose; per frame only L_b's frame (its dot rides on it) and, every few frames,
the herpolhode's newest chunk are sent besides the body, ω and the ghost: the contact point
hangs at ω's tip (`Vector.tip`), and nothing is sent for the hidden line of nodes.
Presets: `assets/presets/poinsot.json` (their angles put L along −z, so the plane is a table
under the body).

The package: `simulation` (the construction's numbers of a run: the Energy setting, the
herpolhode's point; no viser), `readouts` (the Poinsot readout as a pure function), `view`
(`PoinsotView`).
"""

from __future__ import annotations

from app.scenes.poinsot.readouts import poinsot_text
from app.scenes.poinsot.simulation import energy_setting, omega_space, state_at_energy
from app.scenes.poinsot.view import PoinsotView

__all__ = ["PoinsotView", "energy_setting", "omega_space", "poinsot_text", "state_at_energy"]
