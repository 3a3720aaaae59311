"""Tests of physics.inertia against independent references.

References: direct sums of m x × (ω × x) (memo 3.2), the particle tensor about another point,
trimesh's mass properties, closed forms (box; the regular 64-gon prism; bounding cylinders and
balls), the transformation law I' = R I Rᵀ, and constructed tensors Q diag(m) Qᵀ.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import trimesh
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
from scipy.spatial.transform import Rotation

from physics.inertia import (
    InertiaError,
    MassProperties,
    MeshError,
    box_extents_from_moments,
    box_inertia,
    cylinder_dimensions_from_moments,
    inertia_tensor_of_particles,
    mesh_mass_properties,
    parallel_axis,
    principal_axes,
    solid_cylinder_inertia,
    solid_sphere_inertia,
    validate_inertia_tensor,
    validate_principal_moments,
)

RNG_SEED = 20240611

coordinates = st.floats(-10.0, 10.0, allow_nan=False, allow_infinity=False)
particle_masses = st.floats(0.01, 10.0)


@st.composite
def particle_clouds(draw: st.DrawFn, planar: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """(masses (N,), positions (N, 3)) of 4..12 particles; planar clouds lie in a rotated plane."""
    n = draw(st.integers(4, 12))
    masses = draw(hnp.arrays(np.float64, n, elements=particle_masses))
    positions = draw(hnp.arrays(np.float64, (n, 3), elements=coordinates))
    if planar:
        positions[:, 2] = 0.0
        quat = draw(hnp.arrays(np.float64, 4, elements=st.floats(-1.0, 1.0)))
        assume(np.linalg.norm(quat) > 0.1)
        positions = positions @ Rotation.from_quat(quat).as_matrix().T
    return masses, positions


def _not_collinear(masses: np.ndarray, positions: np.ndarray, about: np.ndarray) -> bool:
    """Well away from collinear with `about` (3.8): smallest eigenvalue > 1e-6 × largest."""
    eigenvalues = np.linalg.eigvalsh(inertia_tensor_of_particles(masses, positions, about))
    return bool(eigenvalues[0] > 1e-6 * eigenvalues[2])


# ---------------------------------------------------------------------------------------
# Particles (3.5)-(3.8)
# ---------------------------------------------------------------------------------------


def test_particle_tensor_gives_angular_momentum_of_direct_sum() -> None:
    """I ω = Σ m_i x_i × (ω × x_i) (3.2, 3.5) for random ω, x measured from `about`."""
    rng = np.random.default_rng(RNG_SEED)
    masses = rng.uniform(0.1, 3.0, 17)
    positions = rng.normal(size=(17, 3)) * 2.0
    about = rng.normal(size=3)
    I = inertia_tensor_of_particles(masses, positions, about)
    for _ in range(10):
        omega = rng.normal(size=3)
        L = np.zeros(3)
        for m, x in zip(masses, positions):
            r = x - about
            L += m * np.cross(r, np.cross(omega, r))
        np.testing.assert_allclose(I @ omega, L, rtol=1e-12, atol=1e-12 * np.abs(L).max())
        # T = ½ ω·I ω = ½ Σ m |ω × r|² (3.4, 3.6)
        T = 0.5 * sum(m * np.sum(np.cross(omega, x - about) ** 2) for m, x in zip(masses, positions))
        assert 0.5 * omega @ I @ omega == pytest.approx(T, rel=1e-12)


@settings(max_examples=100, deadline=None)
@given(particle_clouds(), hnp.arrays(np.float64, 3, elements=coordinates))
def test_particle_tensor_symmetric_and_positive_semidefinite(cloud, about) -> None:
    masses, positions = cloud
    I = inertia_tensor_of_particles(masses, positions, about)
    scale = max(float(np.abs(I).max()), 1e-300)
    np.testing.assert_allclose(I, I.T, atol=1e-14 * scale)
    assert np.linalg.eigvalsh(I)[0] >= -1e-12 * scale


def test_collinear_particles_have_one_zero_eigenvalue() -> None:
    """O and all particles on one line: I d = 0 along the line, the rest positive (3.8)."""
    rng = np.random.default_rng(RNG_SEED + 1)
    about = np.array([0.3, -1.0, 2.0])
    direction = np.array([1.0, 2.0, -2.0]) / 3.0
    positions = about + rng.uniform(-2.0, 2.0, (6, 1)) * direction
    masses = rng.uniform(0.5, 2.0, 6)
    I = inertia_tensor_of_particles(masses, positions, about)
    eigenvalues = np.linalg.eigvalsh(I)
    assert abs(eigenvalues[0]) < 1e-14 * eigenvalues[2]
    assert eigenvalues[1] > 0.1
    np.testing.assert_allclose(I @ direction, 0.0, atol=1e-14 * eigenvalues[2])
    with pytest.raises(InertiaError, match="not positive definite"):
        validate_inertia_tensor(I)
    # The same particles seen from a point off their line: positive definite (3.8).
    I_off = inertia_tensor_of_particles(masses, positions, about + np.array([0.0, 0.0, 1.0]))
    assert np.linalg.eigvalsh(I_off)[0] > 1e-3


def test_particle_tensor_rejects_bad_input() -> None:
    with pytest.raises(ValueError):
        inertia_tensor_of_particles([1.0, 2.0], np.zeros((3, 3)))
    with pytest.raises(InertiaError, match="masses"):
        inertia_tensor_of_particles([1.0, -2.0], np.ones((2, 3)))


@settings(max_examples=100, deadline=None)
@given(particle_clouds(), hnp.arrays(np.float64, 3, elements=coordinates))
def test_parallel_axis_matches_tensor_about_other_point(cloud, point) -> None:
    masses, positions = cloud
    total = float(masses.sum())
    cm = masses @ positions / total
    I_cm = inertia_tensor_of_particles(masses, positions, cm)
    I_point = inertia_tensor_of_particles(masses, positions, point)
    # Rounding scale: the cm and the coordinates are O(|x|), so errors are eps·M·|x|².
    # Plus the smallest normal float: a cloud whose tensor is subnormal (Hypothesis found one at
    # 4e-317) rounds to absolute steps of ~5e-324, not relative ones.
    scale = total * (float(np.abs(positions).max()) ** 2 + float(point @ point))
    atol = 1e-12 * scale + np.finfo(float).tiny
    np.testing.assert_allclose(parallel_axis(I_cm, total, cm - point), I_point, atol=atol)
    # The formula is even in the offset: the direction convention cannot change the result.
    np.testing.assert_allclose(parallel_axis(I_cm, total, point - cm), I_point, atol=atol)


# ---------------------------------------------------------------------------------------
# Principal axes
# ---------------------------------------------------------------------------------------


def _check_principal(I: np.ndarray, moments: np.ndarray, R: np.ndarray) -> None:
    scale = float(np.abs(I).max())
    np.testing.assert_allclose(R.T @ R, np.eye(3), atol=1e-14)
    assert np.linalg.det(R) == pytest.approx(1.0, abs=1e-14)
    assert np.all(np.diff(moments) >= 0.0)
    np.testing.assert_allclose(R @ np.diag(moments) @ R.T, I, atol=1e-13 * scale)


@settings(max_examples=150, deadline=None)
@given(
    st.integers(0, 2**32 - 1),
    hnp.arrays(np.float64, 3, elements=st.floats(0.01, 100.0)),
)
def test_principal_axes_recover_constructed_tensor(seed, moments_true) -> None:
    """I = Q diag(m) Qᵀ with a random rotation Q (scipy): moments sorted, axes ±Q columns."""
    Q = Rotation.random(random_state=seed).as_matrix()
    I = Q @ np.diag(moments_true) @ Q.T
    moments, R = principal_axes(I)
    _check_principal(I, moments, R)
    np.testing.assert_allclose(moments, np.sort(moments_true), rtol=1e-12, atol=1e-13 * moments_true.max())
    # Sign convention of columns 1 and 2: the largest-magnitude component is positive.
    for k in (0, 1):
        assert R[int(np.argmax(np.abs(R[:, k]))), k] > 0.0
    # Well-separated moments: each axis is ± the matching column of Q.
    order = np.argsort(moments_true)
    gaps = np.diff(np.sort(moments_true))
    if gaps.min() > 1e-3 * moments_true.max():
        for k in range(3):
            assert abs(R[:, k] @ Q[:, order[k]]) == pytest.approx(1.0, abs=1e-9)


@pytest.mark.parametrize("seed", range(20))
def test_principal_axes_with_repeated_moments(seed: int) -> None:
    """Sphere-like (all equal) and cylinder-like (two equal) tensors in random orientations."""
    Q = Rotation.random(random_state=seed).as_matrix()
    for diag in ([2.0, 2.0, 2.0], [1.0, 1.0, 3.0], [1.0, 3.0, 3.0]):
        I = Q @ np.diag(diag) @ Q.T
        moments, R = principal_axes(I)
        _check_principal(I, moments, R)
        np.testing.assert_allclose(moments, diag, rtol=1e-13)
    # Cylinder-like: the distinct axis is ± Q e_z.
    moments, R = principal_axes(Q @ np.diag([1.0, 1.0, 3.0]) @ Q.T)
    assert abs(R[:, 2] @ Q[:, 2]) == pytest.approx(1.0, abs=1e-12)


def test_principal_axes_deterministic_and_diagonal() -> None:
    I = np.diag([3.0, 1.0, 2.0])
    moments, R = principal_axes(I)
    np.testing.assert_array_equal(moments, [1.0, 2.0, 3.0])
    np.testing.assert_allclose(np.abs(R), [[0, 0, 1], [1, 0, 0], [0, 1, 0]], atol=0)
    moments2, R2 = principal_axes(I.copy())
    np.testing.assert_array_equal(R, R2)


# ---------------------------------------------------------------------------------------
# Validation
# ---------------------------------------------------------------------------------------


def test_lamina_is_accepted() -> None:
    np.testing.assert_array_equal(validate_principal_moments([1, 2, 3]), [1.0, 2.0, 3.0])
    thin_plate = box_inertia(2.0, (0.3, 0.7, 0.0))
    validate_principal_moments(thin_plate)
    # A computed lamina: planar particles in a tilted plane, I3 = I1 + I2 only to rounding.
    rng = np.random.default_rng(RNG_SEED + 2)
    positions = np.column_stack([rng.normal(size=(50, 2)), np.zeros(50)])
    positions = positions @ Rotation.random(random_state=3).as_matrix().T
    I = inertia_tensor_of_particles(rng.uniform(0.1, 1.0, 50), positions, positions.mean(axis=0))
    moments = np.linalg.eigvalsh(I)
    assert moments[0] + moments[1] == pytest.approx(moments[2], rel=1e-13)
    validate_principal_moments(moments)
    validate_inertia_tensor(I)


@pytest.mark.parametrize(
    ("moments", "message"),
    [
        ([1.0, 1.0, 3.0], r"I1 \+ I2 >= I3 fails: 1 \+ 1 < 3"),
        ([5.0, 1.0, 2.0], r"I2 \+ I3 >= I1 fails: 1 \+ 2 < 5"),
        ([1.0, 4.0, 2.0], r"I3 \+ I1 >= I2 fails: 2 \+ 1 < 4"),
        ([1.0, 1.0, 2.0 * (1.0 + 1e-9)], r"I1 \+ I2 >= I3 fails"),
        ([1.0, 0.0, 1.0], r"moment I2 = 0 is not positive"),
        ([1.0, -1.0, 1.0], r"moment I2 = -1 is not positive"),
        ([math.nan, 1.0, 1.0], r"moments must be finite, got nan for I1"),
        ([1.0, 1.0, math.inf], r"moments must be finite, got inf for I3"),
        ([1.0, 2.0], r"shape \(3,\)"),
    ],
)
def test_unphysical_moments_are_rejected_with_named_condition(moments, message) -> None:
    with pytest.raises(InertiaError, match=message):
        validate_principal_moments(moments)


def test_validate_inertia_tensor_rejections() -> None:
    Q = Rotation.from_rotvec([0.3, -0.5, 0.9]).as_matrix()
    with pytest.raises(InertiaError, match=r"I1 \+ I2 >= I3 fails"):
        validate_inertia_tensor(Q @ np.diag([1.0, 1.0, 3.0]) @ Q.T)
    with pytest.raises(InertiaError, match="not symmetric"):
        validate_inertia_tensor(np.diag([2.0, 2.0, 2.0]) + np.triu(np.ones((3, 3)), 1) * 1e-3)
    with pytest.raises(InertiaError, match="not positive definite"):
        validate_inertia_tensor(np.diag([-1.0, 2.0, 2.0]))
    with pytest.raises(InertiaError, match="finite"):
        validate_inertia_tensor(np.diag([math.nan, 2.0, 2.0]))
    with pytest.raises(InertiaError, match="shape"):
        validate_inertia_tensor(np.eye(2))
    I = Q @ np.diag([1.0, 2.0, 2.5]) @ Q.T
    np.testing.assert_allclose(validate_inertia_tensor(I), I, atol=1e-15)


@settings(max_examples=150, deadline=None)
@given(st.one_of(particle_clouds(), particle_clouds(planar=True)))
def test_random_physical_bodies_pass_validation(cloud) -> None:
    """Every body made of particles (solid or flat) passes, about its cm or any point."""
    masses, positions = cloud
    cm = masses @ positions / masses.sum()
    for about in (cm, cm + np.array([1.0, -2.0, 0.5])):
        # A cloud collinear with `about` (e.g. a tiny cloud seen from afar) is rightly refused.
        assume(_not_collinear(masses, positions, about))
        I = inertia_tensor_of_particles(masses, positions, about)
        validate_inertia_tensor(I)
        moments, _ = principal_axes(I)
        validate_principal_moments(moments)


# ---------------------------------------------------------------------------------------
# Meshes
# ---------------------------------------------------------------------------------------


def _trimesh_reference(mesh: trimesh.Trimesh, density: float) -> tuple[float, np.ndarray, np.ndarray]:
    mesh = mesh.copy()
    mesh.density = density
    return float(mesh.mass), np.asarray(mesh.center_mass), np.asarray(mesh.moment_inertia)


def _assert_matches_trimesh(mesh: trimesh.Trimesh, density: float, rtol: float = 1e-12) -> MassProperties:
    props = mesh_mass_properties(mesh.vertices, mesh.faces, density)
    mass, center, inertia = _trimesh_reference(mesh, density)
    size = float(np.linalg.norm(mesh.extents))
    assert props.mass == pytest.approx(mass, rel=rtol)
    assert props.volume == pytest.approx(mesh.volume, rel=rtol)
    np.testing.assert_allclose(props.center_of_mass, center, atol=rtol * size)
    np.testing.assert_allclose(props.inertia_cm, inertia, atol=rtol * np.abs(inertia).max())
    return props


def _random_rigid_transform(seed: int) -> tuple[np.ndarray, np.ndarray]:
    R = Rotation.random(random_state=seed).as_matrix()
    t = np.random.default_rng(seed).uniform(-5.0, 5.0, 3)
    return R, t


def test_box_mesh_is_exact() -> None:
    extents = np.array([0.4, 1.1, 2.3])
    density = 7.5
    box = trimesh.creation.box(extents=extents)
    props = _assert_matches_trimesh(box, density)
    mass = density * float(np.prod(extents))
    assert props.mass == pytest.approx(mass, rel=1e-14)
    np.testing.assert_allclose(props.center_of_mass, 0.0, atol=1e-15)
    np.testing.assert_allclose(props.inertia_cm, np.diag(box_inertia(mass, extents)), rtol=1e-14, atol=1e-15)
    # Rotated and translated: mass, c' = R c + t, I' = R I Rᵀ.
    R, t = _random_rigid_transform(7)
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, t
    moved = box.copy().apply_transform(T)
    props_moved = _assert_matches_trimesh(moved, density)
    assert props_moved.mass == pytest.approx(mass, rel=1e-13)
    np.testing.assert_allclose(props_moved.center_of_mass, t, atol=1e-13)
    np.testing.assert_allclose(props_moved.inertia_cm, R @ props.inertia_cm @ R.T, atol=1e-13)
    moments, R_mesh_principal = props_moved.principal_axes()
    np.testing.assert_allclose(moments, np.sort(box_inertia(mass, extents)), rtol=1e-12)
    # The principal axes are the rotated box edges (moments distinct).
    for k, axis in enumerate(np.argsort(box_inertia(mass, extents))):
        assert abs(R_mesh_principal[:, k] @ R[:, axis]) == pytest.approx(1.0, abs=1e-12)


def test_two_separate_boxes_exact_by_parallel_axes() -> None:
    """A non-convex solid (two disjoint boxes): analytic boxes + parallel axes, exactly."""
    e1, e2 = np.array([1.0, 0.5, 0.25]), np.array([0.3, 0.3, 0.9])
    c1, c2 = np.array([-1.5, 0.2, 0.0]), np.array([1.0, -0.4, 0.7])
    b1 = trimesh.creation.box(extents=e1, transform=trimesh.transformations.translation_matrix(c1))
    b2 = trimesh.creation.box(extents=e2, transform=trimesh.transformations.translation_matrix(c2))
    both = trimesh.util.concatenate([b1, b2])
    density = 2.0
    props = _assert_matches_trimesh(both, density)
    m1, m2 = density * np.prod(e1), density * np.prod(e2)
    cm = (m1 * c1 + m2 * c2) / (m1 + m2)
    expected = parallel_axis(np.diag(box_inertia(m1, e1)), m1, c1 - cm) + parallel_axis(
        np.diag(box_inertia(m2, e2)), m2, c2 - cm
    )
    assert props.mass == pytest.approx(m1 + m2, rel=1e-14)
    np.testing.assert_allclose(props.center_of_mass, cm, atol=1e-14)
    np.testing.assert_allclose(props.inertia_cm, expected, atol=1e-13)


def test_cylinder_mesh_exact_prism_and_tessellation_error() -> None:
    """64-section cylinder = prism over a regular 64-gon of circumradius r.

    Exact prism (per unit density; area A = n/2 r² sin α, α = 2π/n; 2-D second moment of the
    triangle (0, p, q) is det/24 (ppᵀ + qqᵀ + (p+q)(p+q)ᵀ)):  V = A h,
    I_zz = V r² (2 + cos α)/6, I_xx = I_yy = V (r² (2 + cos α)/12 + h²/12).
    Tessellation error against the solid cylinder: volume -α²/6 = -1.6e-3 relative,
    I_zz -α²/3 = -3.2e-3; bounded by the inscribed and circumscribed cylinders.
    """
    r, h, n, density = 0.7, 1.3, 64, 3.0
    cylinder = trimesh.creation.cylinder(radius=r, height=h, sections=n)
    props = _assert_matches_trimesh(cylinder, density)
    alpha = 2.0 * math.pi / n
    volume = 0.5 * n * r * r * math.sin(alpha) * h
    assert props.volume == pytest.approx(volume, rel=1e-13)
    izz = density * volume * r * r * (2.0 + math.cos(alpha)) / 6.0
    ixx = density * volume * (r * r * (2.0 + math.cos(alpha)) / 12.0 + h * h / 12.0)
    np.testing.assert_allclose(props.inertia_cm, np.diag([ixx, ixx, izz]), rtol=1e-13, atol=1e-15)

    # Against the analytic solid cylinder.
    analytic_volume = math.pi * r * r * h
    analytic = solid_cylinder_inertia(density * analytic_volume, r, h)
    assert props.volume / analytic_volume - 1.0 == pytest.approx(-(alpha**2) / 6.0, rel=1e-3)
    assert props.inertia_cm[2, 2] / analytic[2] - 1.0 == pytest.approx(-(alpha**2) / 3.0, rel=2e-3)
    np.testing.assert_allclose(np.diag(props.inertia_cm), analytic, rtol=4e-3)
    # Inscribed cylinder (radius r cos(π/n)) ⊂ prism ⊂ cylinder of radius r: I is monotone.
    r_in = r * math.cos(math.pi / n)
    inner = solid_cylinder_inertia(density * math.pi * r_in**2 * h, r_in, h)
    assert np.all(inner < np.diag(props.inertia_cm)) and np.all(np.diag(props.inertia_cm) < analytic)


def test_icosphere_within_inscribed_and_circumscribed_balls() -> None:
    """Icosphere (3 subdivisions, 1280 faces): ball(r_in) ⊂ mesh ⊂ ball(r), and the moments
    about the centre lie between the two balls' (the integrand r² - x_k² is >= 0).
    Measured tessellation error against the ball of radius r: volume -0.86 %, I -1.43 %."""
    radius, density = 1.5, 0.8
    sphere = trimesh.creation.icosphere(subdivisions=3, radius=radius)
    props = _assert_matches_trimesh(sphere, density)
    normals = np.asarray(sphere.face_normals)
    r_in = float(np.min(np.einsum("ij,ij->i", normals, sphere.vertices[sphere.faces[:, 0]])))
    assert 0.99 * radius < r_in < radius
    I_origin = np.diag(parallel_axis(props.inertia_cm, props.mass, props.center_of_mass))
    outer = solid_sphere_inertia(density * 4.0 / 3.0 * math.pi * radius**3, radius)
    inner = solid_sphere_inertia(density * 4.0 / 3.0 * math.pi * r_in**3, r_in)
    assert np.all(inner < I_origin) and np.all(I_origin < outer)
    assert 4.0 / 3.0 * math.pi * r_in**3 < props.volume < 4.0 / 3.0 * math.pi * radius**3
    np.testing.assert_allclose(props.center_of_mass, 0.0, atol=1e-15)
    assert props.volume / (4.0 / 3.0 * math.pi * radius**3) - 1.0 == pytest.approx(-0.0086, abs=1e-4)
    np.testing.assert_allclose(I_origin / outer - 1.0, -0.0143, atol=1e-4)


@pytest.mark.parametrize("seed", range(5))
def test_random_convex_hull_and_rigid_motion(seed: int) -> None:
    rng = np.random.default_rng(seed)
    points = rng.normal(size=(60, 3)) * rng.uniform(0.2, 3.0, 3)
    hull = trimesh.convex.convex_hull(points)
    density = float(rng.uniform(0.5, 5.0))
    props = _assert_matches_trimesh(hull, density, rtol=1e-11)
    R, t = _random_rigid_transform(seed + 100)
    moved = mesh_mass_properties(hull.vertices @ R.T + t, hull.faces, density)
    assert moved.mass == pytest.approx(props.mass, rel=1e-12)
    np.testing.assert_allclose(moved.center_of_mass, R @ props.center_of_mass + t, atol=1e-11)
    scale = np.abs(props.inertia_cm).max()
    np.testing.assert_allclose(moved.inertia_cm, R @ props.inertia_cm @ R.T, atol=1e-11 * scale)
    validate_inertia_tensor(props.inertia_cm)


def test_annulus_non_convex_matches_trimesh() -> None:
    _assert_matches_trimesh(trimesh.creation.annulus(r_min=0.5, r_max=1.0, height=0.4), 1.7)


def test_mesh_twenty_thousand_faces_matches_trimesh() -> None:
    """A 20480-face sphere (its speed: benchmarks/physics_timings.py) against trimesh."""
    sphere = trimesh.creation.icosphere(subdivisions=5)
    assert len(sphere.faces) == 20480
    _assert_matches_trimesh(sphere, 1.0, rtol=1e-10)


def test_mass_properties_is_frozen() -> None:
    props = mesh_mass_properties(*_box_arrays())
    with pytest.raises(AttributeError):
        props.mass = 2.0  # type: ignore[misc]
    with pytest.raises(ValueError):
        props.inertia_cm[0, 0] = 1.0
    assert props.density == pytest.approx(1.0)


def _box_arrays() -> tuple[np.ndarray, np.ndarray]:
    box = trimesh.creation.box(extents=(1.0, 2.0, 3.0))
    return np.array(box.vertices), np.array(box.faces)


def test_mesh_errors() -> None:
    vertices, faces = _box_arrays()
    with pytest.raises(MeshError, match="open mesh"):
        mesh_mass_properties(vertices, faces[1:])
    with pytest.raises(MeshError, match="inside out"):
        mesh_mass_properties(vertices, faces[:, ::-1])
    flipped_one = faces.copy()
    flipped_one[3] = flipped_one[3, ::-1]
    with pytest.raises(MeshError, match="same direction"):
        mesh_mass_properties(vertices, flipped_one)
    bad = vertices.copy()
    bad[2, 1] = math.nan
    with pytest.raises(MeshError, match="vertex 2 is not finite"):
        mesh_mass_properties(bad, faces)
    bad[2, 1] = math.inf
    with pytest.raises(MeshError, match="not finite"):
        mesh_mass_properties(bad, faces)
    too_big = faces.copy()
    too_big[5, 1] = len(vertices)
    with pytest.raises(MeshError, match="face 5 .* outside"):
        mesh_mass_properties(vertices, too_big)
    negative = faces.copy()
    negative[0, 0] = -1
    with pytest.raises(MeshError, match="outside"):
        mesh_mass_properties(vertices, negative)
    with pytest.raises(MeshError, match="shape"):
        mesh_mass_properties(vertices[:, :2], faces)
    with pytest.raises(MeshError, match="shape"):
        mesh_mass_properties(vertices, faces[:, :2])
    with pytest.raises(MeshError, match="integer"):
        mesh_mass_properties(vertices, faces.astype(float))
    with pytest.raises(MeshError, match="repeats a vertex"):
        mesh_mass_properties(vertices, np.vstack([faces, [[0, 0, 1]]]))
    with pytest.raises(MeshError, match="density"):
        mesh_mass_properties(vertices, faces, density=0.0)
    # A closed, consistently oriented but flat surface: two triangles back to back.
    flat = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    with pytest.raises(MeshError, match="zero volume"):
        mesh_mass_properties(flat, np.array([[0, 1, 2], [0, 2, 1]]))
    # MeshError is a ValueError (callers may catch either).
    assert issubclass(MeshError, ValueError) and issubclass(InertiaError, ValueError)


# ---------------------------------------------------------------------------------------
# Analytic bodies and the equivalent box
# ---------------------------------------------------------------------------------------


def test_analytic_moments_reference_values() -> None:
    np.testing.assert_allclose(box_inertia(12.0, (1.0, 2.0, 3.0)), [13.0, 10.0, 5.0])
    np.testing.assert_allclose(solid_cylinder_inertia(12.0, 1.0, 2.0), [7.0, 7.0, 6.0])
    np.testing.assert_allclose(solid_sphere_inertia(5.0, 2.0), [8.0, 8.0, 8.0])
    with pytest.raises(ValueError):
        solid_sphere_inertia(-1.0, 1.0)
    with pytest.raises(ValueError):
        box_inertia(1.0, (1.0, -1.0, 1.0))


@settings(max_examples=150, deadline=None)
@given(
    hnp.arrays(np.float64, 3, elements=st.one_of(st.just(0.0), st.floats(1e-3, 10.0))),
    st.floats(0.01, 100.0),
)
def test_box_extents_invert_box_inertia(extents, mass) -> None:
    assume(np.count_nonzero(extents) >= 2)  # at most one zero edge (a plate)
    moments = box_inertia(mass, extents)
    recovered = box_extents_from_moments(moments, mass)
    np.testing.assert_allclose(recovered, extents, atol=1e-6 * extents.max())


def test_box_extents_of_lamina_and_rejections() -> None:
    extents = box_extents_from_moments([1.0, 2.0, 3.0], 6.0)
    np.testing.assert_allclose(extents, [2.0, math.sqrt(2.0), 0.0])
    np.testing.assert_allclose(box_inertia(6.0, extents), [1.0, 2.0, 3.0], rtol=1e-15)
    with pytest.raises(InertiaError, match=r"I1 \+ I2 >= I3 fails"):
        box_extents_from_moments([1.0, 1.0, 3.0], 1.0)
    with pytest.raises(ValueError, match="mass"):
        box_extents_from_moments([1.0, 1.0, 1.0], 0.0)


# --- cylinder_dimensions_from_moments against trimesh's mesh inertia -------------------------


@pytest.mark.parametrize(("radius", "height", "mass"), [(0.5, 1.2, 1.0), (1.0, 0.1, 3.0), (0.2, 2.0, 0.5)])
def test_cylinder_dimensions_invert_trimesh_cylinder_moments(radius: float, height: float, mass: float) -> None:
    """A fine trimesh cylinder's moments (scaled to `mass`) give back its radius and height."""
    mesh = trimesh.creation.cylinder(radius=radius, height=height, sections=1024)
    moments = np.diag(mesh.moment_inertia) * mass / mesh.mass  # about the centroid, axis z
    assert moments[0] == pytest.approx(moments[1], rel=1e-9)
    r, h = cylinder_dimensions_from_moments(moments[0], moments[2], mass=mass)
    # a 1024-gon has 1e-5 less area than the circle: dimensions agree to ~1e-5
    assert r == pytest.approx(radius, rel=1e-4)
    assert h == pytest.approx(height, rel=1e-4)
    np.testing.assert_allclose(solid_cylinder_inertia(mass, r, h), [moments[0], moments[0], moments[2]], rtol=1e-12)


def test_cylinder_dimensions_edge_cases() -> None:
    r, h = cylinder_dimensions_from_moments(0.5, 1.0)  # I1 = I3/2: the flat disc
    assert (r, h) == (math.sqrt(2.0), 0.0)
    with pytest.raises(InertiaError, match="I3/2"):
        cylinder_dimensions_from_moments(0.4, 1.0)
    with pytest.raises(ValueError):
        cylinder_dimensions_from_moments(-1.0, 1.0)
    with pytest.raises(ValueError, match="mass"):
        cylinder_dimensions_from_moments(1.0, 1.0, mass=0.0)
