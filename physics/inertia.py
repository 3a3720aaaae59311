"""Inertia tensors (memo §3): particles, polyhedral meshes, principal axes, validation.

Conventions (docs/CONVENTIONS.md, memo 3.1-3.8):

* The inertia tensor about a point O of particles at x_i (vectors from O, space or body
  components alike) is ``I = Σ m_i (|x_i|² 1 - x_i x_iᵀ)`` (3.5), so that ``L = I ω`` and
  ``T = ½ ω·I ω`` (3.6).  Units: mass [kg], lengths [m], moments [kg m²].
* I is symmetric and positive semidefinite; positive definite unless O and all particles
  are collinear (3.8).  Its eigenvalues, the principal moments, of any physical body satisfy
  the triangle inequalities I1 + I2 ≥ I3 (and cyclic); equality is a flat lamina.  Moments
  that break them are not a body and raise `InertiaError`, whose message names the condition.
* Parallel axes: ``I_O = I_cm + m (|c|² 1 - c cᵀ)`` with c = (centre of mass) - O.
* `principal_axes` returns ``R_ref_principal`` whose columns are the principal axes in the
  reference (e.g. mesh) axes: ``I = R diag(moments) Rᵀ``, moments ascending, det R = +1.

Pure NumPy: this module never imports trimesh (a trimesh mesh is passed as
``mesh.vertices, mesh.faces``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from physics._types import Mat3, Vec3
from physics.refusal import N_, Refusal

__all__ = [
    "InertiaError",
    "MassProperties",
    "MeshError",
    "box_extents_from_moments",
    "box_inertia",
    "cylinder_dimensions_from_moments",
    "inertia_tensor_of_particles",
    "mesh_mass_properties",
    "parallel_axis",
    "principal_axes",
    "principal_axes_near",
    "solid_cylinder_inertia",
    "solid_sphere_inertia",
    "validate_inertia_tensor",
    "validate_principal_moments",
]

# Relative slack on the triangle inequality, in units of I1 + I2 + I3, so that a lamina
# computed in floating point (I3 = I1 + I2 up to rounding) is accepted.
TRIANGLE_RTOL = 1e-12
# Relative tolerance on the asymmetry of a tensor, in units of its largest entry.
SYMMETRY_RTOL = 1e-10
# A tensor whose smallest eigenvalue is <= this times its largest is treated as singular
# (collinear particles give an exact zero that rounding turns into ±1e-16 * largest).
DEFINITE_RTOL = 1e-12
# A closed mesh whose |volume| is <= this times (bounding-box diagonal)³ has zero volume.
ZERO_VOLUME_RTOL = 1e-12


class InertiaError(Refusal):
    """Moments or a tensor that no physical body has; the message names the failing test
    (`template` and `fields`: `physics.refusal.Refusal`, for an app that translates it)."""


class MeshError(Refusal):
    """A mesh that does not bound a solid: bad shapes or indices, open, inside out, flat
    (`template` and `fields`: `physics.refusal.Refusal`)."""


def _fmt(x: float) -> str:
    return f"{x:.15g}"


# ---------------------------------------------------------------------------------------
# Validation
# ---------------------------------------------------------------------------------------


def validate_principal_moments(moments: ArrayLike) -> Vec3:
    """Check (I1, I2, I3) [kg m²] (3,) are the principal moments of a body; return a copy.

    Conditions, checked in this order: shape (3,); finite; each moment > 0; the triangle
    inequalities I1 + I2 ≥ I3, I2 + I3 ≥ I1, I3 + I1 ≥ I2 (in the order given, not sorted).
    Equality is allowed (a flat lamina), with a rounding slack of
    ``TRIANGLE_RTOL * (I1 + I2 + I3)`` so that a computed lamina passes.

    Raises:
        InertiaError: naming the first failing condition, e.g.
            ``"I1 + I2 >= I3 fails: 1 + 1 < 3"``.
    """
    m = np.array(moments, dtype=float)
    if m.shape != (3,):
        raise InertiaError(N_("principal moments must have shape (3,), got {shape}"), shape=m.shape)
    for k in range(3):
        if not math.isfinite(m[k]):
            raise InertiaError(N_("moments must be finite, got {value} for I{k}"), value=_fmt(m[k]), k=k + 1)
    for k in range(3):
        if not m[k] > 0.0:
            raise InertiaError(N_("moment I{k} = {value} is not positive"), k=k + 1, value=_fmt(m[k]))
    slack = TRIANGLE_RTOL * float(m.sum())
    for i, j, k in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
        if m[i] + m[j] < m[k] - slack:
            raise InertiaError(
                N_("I{i} + I{j} >= I{k} fails: {a} + {b} < {c}"),
                i=i + 1, j=j + 1, k=k + 1, a=_fmt(m[i]), b=_fmt(m[j]), c=_fmt(m[k]),
            )
    return m


def validate_inertia_tensor(I: ArrayLike) -> Mat3:
    """Check that I (3, 3) [kg m²] is the inertia tensor of a body; return it symmetrised.

    Conditions, in order: shape (3, 3); finite; symmetric to ``SYMMETRY_RTOL`` times the
    largest entry; positive definite (smallest eigenvalue > ``DEFINITE_RTOL`` times the
    largest, so collinear particles (3.8) are refused); eigenvalues satisfy the triangle
    inequalities (see `validate_principal_moments`).

    Raises:
        InertiaError: naming the failing condition.
    """
    A = np.array(I, dtype=float)
    if A.shape != (3, 3):
        raise InertiaError(N_("inertia tensor must have shape (3, 3), got {shape}"), shape=A.shape)
    if not np.all(np.isfinite(A)):
        raise InertiaError(N_("inertia tensor must be finite, got {tensor}"), tensor=A.tolist())
    scale = float(np.max(np.abs(A)))
    asym = float(np.max(np.abs(A - A.T)))
    if asym > SYMMETRY_RTOL * scale:
        raise InertiaError(
            N_("inertia tensor is not symmetric: max |I - I^T| = {asymmetry} > {rtol} * max |I| = {allowed}"),
            asymmetry=f"{asym:.3g}", rtol=f"{SYMMETRY_RTOL:g}", allowed=f"{SYMMETRY_RTOL * scale:.3g}",
        )
    A = 0.5 * (A + A.T)
    eigenvalues = np.linalg.eigvalsh(A)  # ascending
    if not (eigenvalues[2] > 0.0 and eigenvalues[0] > DEFINITE_RTOL * eigenvalues[2]):
        raise InertiaError(
            N_("inertia tensor is not positive definite: eigenvalues ({a}, {b}, {c}) "
               "(collinear mass distribution or a non-physical tensor)"),
            a=_fmt(eigenvalues[0]), b=_fmt(eigenvalues[1]), c=_fmt(eigenvalues[2]),
        )
    validate_principal_moments(eigenvalues)
    return A


# ---------------------------------------------------------------------------------------
# Particles, parallel axes, principal axes
# ---------------------------------------------------------------------------------------


def inertia_tensor_of_particles(
    masses: ArrayLike, positions: ArrayLike, about: ArrayLike = (0.0, 0.0, 0.0)
) -> Mat3:
    """Inertia tensor (3, 3) [kg m²] of point masses about the point `about` (memo 3.5).

    ``I = Σ m_i (|x_i|² 1 - x_i x_iᵀ)`` with x_i = positions[i] - about.

    Args:
        masses: (N,) [kg], finite and >= 0.
        positions: (N, 3) [m], in any frame; I comes out in the same axes.
        about: (3,) [m], the reference point O in the same frame.
    """
    m = np.asarray(masses, dtype=float)
    x = np.asarray(positions, dtype=float)
    o = np.asarray(about, dtype=float)
    if m.ndim != 1 or x.shape != (m.shape[0], 3) or o.shape != (3,):
        raise ValueError(
            f"need masses (N,), positions (N, 3), about (3,); got {m.shape}, {x.shape}, {o.shape}"
        )
    if not np.all(np.isfinite(m)) or np.any(m < 0.0):
        raise InertiaError(N_("masses must be finite and >= 0, got {masses}"), masses=m.tolist())
    r = x - o
    second_moment = (r * m[:, None]).T @ r  # Σ m r rᵀ
    return np.trace(second_moment) * np.eye(3) - second_moment


def parallel_axis(I_cm: ArrayLike, mass: float, offset: ArrayLike) -> Mat3:
    """Inertia tensor (3, 3) [kg m²] about a point O from the one about the centre of mass.

    ``I_O = I_cm + m (|c|² 1 - c cᵀ)``, c = `offset` = (centre of mass) - O [m], in the axes of
    `I_cm` (the centre of mass seen from O; the formula is even in c, so -c gives the same).
    The reverse shift, from O to the centre of mass, is ``I_cm = I_O - m (|c|² 1 - c cᵀ)``:
    it is only valid with the centre of mass as the base point.

    Args:
        I_cm: (3, 3) [kg m²] about the centre of mass.
        mass: total mass [kg].
        offset: (3,) [m].
    """
    A = np.asarray(I_cm, dtype=float)
    c = np.asarray(offset, dtype=float)
    if A.shape != (3, 3) or c.shape != (3,):
        raise ValueError(f"need I_cm (3, 3) and offset (3,); got {A.shape}, {c.shape}")
    return A + float(mass) * (float(c @ c) * np.eye(3) - np.outer(c, c))


def principal_axes(I: ArrayLike) -> tuple[Vec3, Mat3]:
    """Principal moments (3,) ascending [kg m²] and R_ref_principal (3, 3), det +1.

    The columns of R_ref_principal are the principal axes in the axes of I ("ref"), so
    ``I = R diag(moments) Rᵀ`` and ``v_ref = R_ref_principal @ v_principal``.  Any symmetric I
    is accepted (no physical check; see `validate_inertia_tensor`).

    Sign convention (deterministic): columns 1 and 2 have their largest-magnitude component
    positive (first such index on ties); column 3 = column 1 × column 2, so det = +1.
    Repeated moments: the eigenspace has no preferred basis; an orthonormal one is returned
    (from LAPACK ``eigh``), re-orthonormalised so R is orthonormal to rounding (~1e-16).
    """
    A = np.asarray(I, dtype=float)
    if A.shape != (3, 3):
        raise ValueError(f"inertia tensor must have shape (3, 3), got {A.shape}")
    if not np.all(np.isfinite(A)):
        raise ValueError("inertia tensor must be finite")
    A = 0.5 * (A + A.T)
    moments, vectors = np.linalg.eigh(A)  # ascending, orthonormal columns
    e1 = vectors[:, 0] / np.linalg.norm(vectors[:, 0])
    e2 = vectors[:, 1] - (e1 @ vectors[:, 1]) * e1
    e2 = e2 / np.linalg.norm(e2)
    if e1[int(np.argmax(np.abs(e1)))] < 0.0:
        e1 = -e1
    if e2[int(np.argmax(np.abs(e2)))] < 0.0:
        e2 = -e2
    e3 = np.cross(e1, e2)
    R = np.column_stack([e1, e2, e3])
    return moments.astype(float), R


def principal_axes_near(
    I: ArrayLike, previous: ArrayLike, rtol: float = 1e-6
) -> tuple[Vec3, Mat3, list[list[int]]]:
    """Principal moments (3,) ascending, the principal axes (3, 3) closest to `previous`, and
    the groups of equal moments.

    Where moments are equal (within ``rtol`` times the largest) the eigenvectors are not
    determined (3.8): any orthonormal basis of the eigenspace is principal.  For each such group
    of columns this picks the basis closest to the same columns of `previous` in the Frobenius
    norm (the orthogonal polar factor of Vᵀ P, V an eigenbasis, P the previous columns), so a
    frame drawn from it does not jump while a body is dragged through an isotropic or symmetric
    configuration.  A single column gets the sign of its previous one.  det = +1: if the choices
    above give -1, the column least aligned with its previous one is reversed.

    Args:
        I: (3, 3) symmetric [kg m²].
        previous: (3, 3) the axes last used (columns, orthonormal, det +1).
        rtol: moments within ``rtol * max(|moments|)`` of each other are equal.

    Returns:
        moments (3,) ascending, R_ref_principal (3, 3) with I = R diag(moments) Rᵀ, and the
        groups of column indices with equal moments (e.g. ``[[0, 1]]`` when I1 = I2; all
        three: ``[[0, 1, 2]]``).
    """
    moments, axes = principal_axes(I)
    P = np.asarray(previous, dtype=float)
    if P.shape != (3, 3) or not np.all(np.isfinite(P)):
        raise ValueError(f"previous axes must be a finite (3, 3), got shape {P.shape}")
    tolerance = rtol * float(np.max(np.abs(moments)))
    groups: list[list[int]] = [[0]]
    for k in (1, 2):
        if float(moments[k] - moments[k - 1]) <= tolerance:
            groups[-1].append(k)
        else:
            groups.append([k])
    R = np.array(axes)
    for group in groups:
        V, Pg = axes[:, group], P[:, group]
        if len(group) == 1:
            if float(V[:, 0] @ Pg[:, 0]) < 0.0:
                R[:, group] = -V
            continue
        U, _, Wt = np.linalg.svd(V.T @ Pg)
        R[:, group] = V @ (U @ Wt)
    if np.linalg.det(R) < 0.0:
        j = int(np.argmin(np.abs(np.einsum("ij,ij->j", R, P))))
        R[:, j] = -R[:, j]
    return moments, R, [g for g in groups if len(g) > 1]


# ---------------------------------------------------------------------------------------
# Polyhedral meshes
# ---------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class MassProperties:
    """Mass properties of a uniform solid (arrays are read-only).

    Attributes:
        mass: [kg].
        volume: [m³], > 0.
        center_of_mass: (3,) [m], in the mesh axes.
        inertia_cm: (3, 3) [kg m²], about the centre of mass, in the mesh axes.

    ``eq=False``: comparing arrays with ``==`` has no single truth value; compare fields.
    """

    mass: float
    volume: float
    center_of_mass: Vec3
    inertia_cm: Mat3

    def __post_init__(self) -> None:
        for name in ("center_of_mass", "inertia_cm"):
            value = np.array(getattr(self, name), dtype=float)
            value.setflags(write=False)
            object.__setattr__(self, name, value)

    @property
    def density(self) -> float:
        """mass / volume [kg/m³]."""
        return self.mass / self.volume

    def principal_axes(self) -> tuple[Vec3, Mat3]:
        """`principal_axes` of `inertia_cm`: moments (3,) ascending, R_mesh_principal (3, 3)."""
        return principal_axes(self.inertia_cm)


def _check_closed_and_oriented(faces: NDArray[np.int64], n_vertices: int) -> None:
    """Every edge shared by exactly two faces that traverse it in opposite directions.

    Equivalent test on half-edges (f0,f1), (f1,f2), (f2,f0): no half-edge occurs twice, and
    the sorted list of half-edges equals the sorted list of their reverses.
    """
    heads = faces.reshape(-1)
    tails = faces[:, [1, 2, 0]].reshape(-1)
    n = np.int64(n_vertices)
    keys = np.sort(heads * n + tails)
    repeated = keys[1:] == keys[:-1]
    if np.any(repeated):
        i, j = divmod(int(keys[int(np.argmax(repeated))]), n_vertices)
        raise MeshError(
            N_("edge ({i}, {j}) is traversed in the same direction by two faces: "
               "inconsistent face orientation or a non-manifold edge"),
            i=i, j=j,
        )
    reverse_keys = np.sort(tails * n + heads)
    if not np.array_equal(keys, reverse_keys):
        # Find a half-edge whose reverse is absent (for the message only).
        position = np.minimum(np.searchsorted(keys, tails * n + heads), keys.size - 1)
        missing = keys[position] != tails * n + heads
        h = int(np.argmax(missing))
        raise MeshError(
            N_("open mesh: edge ({i}, {j}) of face {face} has no opposite edge in another face "
               "(a boundary edge, or a neighbour with the wrong orientation)"),
            i=int(heads[h]), j=int(tails[h]), face=h // 3,
        )


def mesh_mass_properties(
    vertices: ArrayLike, faces: ArrayLike, density: float = 1.0
) -> MassProperties:
    """Exact mass properties of the uniform solid bounded by a closed triangle mesh.

    Method: the divergence theorem splits the solid into signed tetrahedra (p, a, b, c), one
    per face (a, b, c), with p a fixed reference point (the mean vertex, to limit
    cancellation).  With a, b, c taken relative to p, d = det[a b c] and s = a + b + c:
    volume ``Σ d/6``, first moment ``Σ d/24 s``, second moment
    ``Σ d/120 (a aᵀ + b bᵀ + c cᵀ + s sᵀ)`` (Tonon 2004; the canonical tetrahedron's covariance).
    These are exact for any polyhedron, so a box is exact to rounding.  Vectorised: a
    20k-face mesh takes a few milliseconds.

    Args:
        vertices: (V, 3) [m], finite.  (trimesh: ``mesh.vertices``)
        faces: (F, 3) integer indices into vertices, counter-clockwise seen from outside
            (outward normals).  (trimesh: ``mesh.faces``)
        density: [kg/m³], > 0.

    Raises:
        MeshError: wrong shapes, non-finite vertices, face indices out of range, a face
            repeating a vertex, an open mesh (some edge not shared by exactly two faces of
            opposite orientation), an inside-out mesh (negative volume), zero volume.
            Not checked: self-intersections (the result is then a signed-volume sum).
    """
    v = np.asarray(vertices, dtype=float)
    f_in = np.asarray(faces)
    if v.ndim != 2 or v.shape[1] != 3 or v.shape[0] == 0:
        raise MeshError(N_("vertices must have shape (V, 3) with V > 0, got {shape}"), shape=v.shape)
    if f_in.ndim != 2 or f_in.shape[1] != 3 or f_in.shape[0] == 0:
        raise MeshError(N_("faces must have shape (F, 3) with F > 0, got {shape}"), shape=f_in.shape)
    if not np.issubdtype(f_in.dtype, np.integer):
        raise MeshError(N_("faces must be integer indices, got dtype {dtype}"), dtype=f_in.dtype)
    if not (math.isfinite(density) and density > 0.0):
        raise MeshError(N_("density must be finite and > 0, got {density}"), density=density)
    bad_vertex = ~np.all(np.isfinite(v), axis=1)
    if np.any(bad_vertex):
        k = int(np.argmax(bad_vertex))
        raise MeshError(N_("vertex {k} is not finite: {vertex}"), k=k, vertex=v[k].tolist())
    f = f_in.astype(np.int64)
    out_of_range = (f < 0) | (f >= v.shape[0])
    if np.any(out_of_range):
        k = int(np.argmax(np.any(out_of_range, axis=1)))
        raise MeshError(N_("face {k} = {face} has an index outside [0, {last}]"), k=k, face=f[k].tolist(),
                        last=v.shape[0] - 1)
    repeated = (f[:, 0] == f[:, 1]) | (f[:, 1] == f[:, 2]) | (f[:, 2] == f[:, 0])
    if np.any(repeated):
        k = int(np.argmax(repeated))
        raise MeshError(N_("face {k} = {face} repeats a vertex"), k=k, face=f[k].tolist())
    _check_closed_and_oriented(f, v.shape[0])

    used = np.zeros(v.shape[0], dtype=bool)
    used[f.reshape(-1)] = True
    v_used = v[used]
    reference = v_used.mean(axis=0)
    # Work in (3, F) layout: contiguous rows make the gathers and products fast.
    v_rel_t = np.ascontiguousarray((v - reference).T)  # (3, V), relative to the reference
    f_t = np.ascontiguousarray(f.T)  # (3, F)
    a = np.take(v_rel_t, f_t[0], axis=1)
    b = np.take(v_rel_t, f_t[1], axis=1)
    c = np.take(v_rel_t, f_t[2], axis=1)
    # d = a · (b × c) = 6 × signed tetrahedron volume (written out: np.cross is slow).
    d = (
        a[0] * (b[1] * c[2] - b[2] * c[1])
        + a[1] * (b[2] * c[0] - b[0] * c[2])
        + a[2] * (b[0] * c[1] - b[1] * c[0])
    )
    s = a + b + c
    volume = float(d.sum()) / 6.0

    extent = float(np.linalg.norm(v_used.max(axis=0) - v_used.min(axis=0)))
    if abs(volume) <= ZERO_VOLUME_RTOL * extent**3:
        raise MeshError(N_("mesh encloses zero volume ({volume} m^3)"), volume=f"{volume:.3g}")
    if volume < 0.0:
        raise MeshError(
            N_("mesh is inside out (signed volume {volume} m^3 < 0): faces must be "
               "counter-clockwise seen from outside"),
            volume=f"{volume:.6g}",
        )

    centroid = (s @ d) / 24.0 / volume  # ∫ x dV / V, relative to the reference
    # ∫ x xᵀ dV about the reference: Σ d/120 (a aᵀ + b bᵀ + c cᵀ + s sᵀ).
    second = (
        (a * d) @ a.T + (b * d) @ b.T + (c * d) @ c.T + (s * d) @ s.T
    ) / 120.0
    second_cm = second - volume * np.outer(centroid, centroid)
    second_cm = 0.5 * (second_cm + second_cm.T)
    inertia_cm = density * (np.trace(second_cm) * np.eye(3) - second_cm)
    return MassProperties(
        mass=density * volume,
        volume=volume,
        center_of_mass=reference + centroid,
        inertia_cm=inertia_cm,
    )


# ---------------------------------------------------------------------------------------
# Analytic bodies (principal moments about the centre of mass)
# ---------------------------------------------------------------------------------------


def _positive(name: str, value: float) -> float:
    value = float(value)
    if not (math.isfinite(value) and value > 0.0):
        raise ValueError(f"{name} must be finite and > 0, got {value}")
    return value


def box_inertia(mass: float, extents: ArrayLike) -> Vec3:
    """Principal moments (3,) [kg m²] of a uniform box with edge lengths (a, b, c) [m].

    ``m/12 (b² + c², a² + c², a² + b²)`` about the box axes through its centre.  One zero
    extent gives a flat plate (I3 = I1 + I2 when c = 0).
    """
    m = _positive("mass", mass)
    e = np.asarray(extents, dtype=float)
    if e.shape != (3,) or not np.all(np.isfinite(e)) or np.any(e < 0.0):
        raise ValueError(f"extents must be (3,) finite and >= 0, got {e.tolist()}")
    a2, b2, c2 = e * e
    return m / 12.0 * np.array([b2 + c2, a2 + c2, a2 + b2])


def solid_cylinder_inertia(mass: float, radius: float, height: float) -> Vec3:
    """Principal moments (3,) [kg m²] of a uniform solid cylinder, axis z, about its centre.

    ``(m(3r² + h²)/12, m(3r² + h²)/12, m r²/2)``.
    """
    m = _positive("mass", mass)
    r = _positive("radius", radius)
    h = float(height)
    if not (math.isfinite(h) and h >= 0.0):
        raise ValueError(f"height must be finite and >= 0, got {height}")
    transverse = m * (3.0 * r * r + h * h) / 12.0
    return np.array([transverse, transverse, 0.5 * m * r * r])


def solid_sphere_inertia(mass: float, radius: float) -> Vec3:
    """Principal moments (3,) [kg m²] of a uniform solid ball: ``2/5 m r²`` each."""
    m = _positive("mass", mass)
    r = _positive("radius", radius)
    return np.full(3, 0.4 * m * r * r)


def box_extents_from_moments(moments: ArrayLike, mass: float) -> Vec3:
    """Edge lengths (a, b, c) (3,) [m] of the uniform box with principal moments (I1, I2, I3).

    Inverts `box_inertia`: ``a² = 6 (I2 + I3 - I1)/m`` and cyclic, so each extent lies along
    the axis of the moment in the same position.  A body is drawn as this "equivalent box".
    The moments are validated first (`InertiaError` otherwise); for a flat lamina
    (I3 = I1 + I2) the extent c is 0 (a squared extent below zero by rounding is clipped).
    """
    I1, I2, I3 = validate_principal_moments(moments)
    m = _positive("mass", mass)
    squares = 6.0 / m * np.array([I2 + I3 - I1, I3 + I1 - I2, I1 + I2 - I3])
    return np.sqrt(np.clip(squares, 0.0, None))


def cylinder_dimensions_from_moments(I1: float, I3: float, mass: float = 1.0) -> tuple[float, float]:
    """(radius, height) [m] of the uniform solid cylinder about z' with these principal moments.

    Inverts `solid_cylinder_inertia`: I3 = m r²/2 and I1 = I2 = m (3 r² + h²)/12 give
    ``r² = 2 I3/m`` and ``h² = 12 I1/m - 3 r² = (12 I1 - 6 I3)/m``.  I1 = I3/2 is the flat disc
    (h = 0); I1 < I3/2 is no cylinder (the triangle inequality 2 I1 >= I3 of a symmetric body).

    Raises:
        InertiaError (a ValueError): I1, I3 not finite and positive, or I1 < I3/2 (beyond
            rounding: a squared height of -1e-15 relative is taken as 0).
        ValueError: mass not finite and positive.
    """
    m = _positive("mass", mass)
    i1, i3 = float(I1), float(I3)
    if not (math.isfinite(i1) and math.isfinite(i3) and i1 > 0.0 and i3 > 0.0):
        raise InertiaError(N_("moments must be finite and > 0, got I1 = {I1}, I3 = {I3}"), I1=_fmt(i1), I3=_fmt(i3))
    height_squared = (12.0 * i1 - 6.0 * i3) / m
    if height_squared < -1e-15 * 12.0 * i1 / m:
        raise InertiaError(
            N_("no uniform cylinder has I1 = {I1} < I3/2 = {half_I3} (the flat disc has I1 = I3/2)"),
            I1=_fmt(i1), half_I3=_fmt(i3 / 2),
        )
    return math.sqrt(2.0 * i3 / m), math.sqrt(max(height_squared, 0.0))

