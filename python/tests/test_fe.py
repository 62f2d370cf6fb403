"""The finite-element continuum reference (esph.fe): its table and cross-checks.

(a) the truss at nu = 0 is homogeneous: the table and a fresh FE solve
    against the exact 1-D SVK bar, P = E lam (lam^2 - 1)/2;
(b) the beam at -10 N, nu = 0 against Reissner's shear beam
    (theory.shear_beam_tip), and the linear limit against the independent
    linear Q9 code studies/beam_error/fe_continuum.py;
(c) patch tests: a homogeneous SVK stretch on distorted meshes (2D, 3D);
(d) a coarse recomputation of a stored beam entry, and 3D consistency
    (half-z model = full model, 3D nu = 0 = 2D plane stress);
(e) the beam under its own weight (body force, table fe_bodyforce.json):
    the table, the load vector (exactly the weight), linearity at small g,
    the Timoshenko beam and the exact plane-elasticity (polynomial) solution;
(f) the beam clamped to a rigid cylinder under its own weight (table
    fe_cylinder.json): the exactly mapped mesh (area, clamped arc), the
    corner angle and exponents, the large-R limit against the straight-clamp
    table fe_bodyforce.json, and the table itself (if present).
"""
from __future__ import annotations

import functools
import math
import sys
from pathlib import Path

import numpy as np
import pytest

skfem = pytest.importorskip("skfem")

from esph import fe, theory  # noqa: E402

STUDIES = Path(__file__).resolve().parents[2] / "studies" / "beam_error"


def exact_truss_stretch(load: float, truss: fe.Problem) -> float:
    """lam^3 - lam - 2 F/(A E) = 0, the root continuous from lam = 1 (Newton)."""
    s = load / (truss.H * truss.t * truss.E)
    lam = 1.0 + s
    for _ in range(50):
        step = (lam ** 3 - lam - 2.0 * s) / (3.0 * lam ** 2 - 1.0)
        lam -= step
        if abs(step) < 1e-16:
            break
    return lam


# -- the table ----------------------------------------------------------------

def test_table_covers_every_case():
    for name, pr in fe.PROBLEMS.items():
        for nu, plane in pr.cases:
            for load in pr.loads:
                for dx in pr.dxs:
                    r = fe.tip(name, load, dx, nu=nu, plane=plane)
                    assert set(r) >= {"dh", "dv", "error_estimate"}
                    assert (pr.dim == 3) == ("dz" in r)
                    assert r["error_estimate"] >= 0.0


def test_tip_missing_case_names_it_and_the_command():
    with pytest.raises(KeyError) as err:
        fe.tip("beam", -11.0, 0.002, nu=0.3, plane="stress")
    msg = str(err.value)
    assert "load=-11" in msg and "dx=0.002" in msg and "nu=0.3" in msg
    assert "python -m esph.fe --write" in msg
    with pytest.raises(KeyError, match="no problem"):
        fe.tip("plate", -10.0, 0.002)


def test_table_meets_the_convergence_targets():
    """2D entries converged to 2e-6 (relative Richardson estimate), except the
    compressed nu = 0.3 plane-strain truss at -5000/-7000 N, where SVK's
    compressive softening at the clamped corners limits the mesh (table
    meta note): those to 2e-5.  3D: the stated estimates are consistent with
    the meta (targets 2e-5; see the meta note on nu = 0.3)."""
    table = fe._load_table()
    for name in ("beam", "truss"):
        for e in table["problems"][name]["entries"]:
            exempt = (name == "truss" and e["nu"] == 0.3 and e["plane"] == "strain"
                      and e["load"] <= -5000.0)
            assert e["error_estimate"] < (2e-5 if exempt else 2e-6), e
    for name in ("beam3d", "beam3d_short"):
        part = table["problems"][name]
        worst = max(e["error_estimate"] for e in part["entries"])
        assert worst == pytest.approx(part["meta"]["max_error_estimate"])
        assert worst < 2e-4


def test_symmetric_components_vanish():
    for dx in fe.PROBLEMS["truss"].dxs:
        for load in (7000.0, -7000.0):
            r = fe.tip("truss", load, dx, nu=0.3)
            assert abs(r["dv"]) < 1e-12 * abs(r["dh"])
    for name in ("beam3d", "beam3d_short"):
        pr = fe.PROBLEMS[name]
        r = fe.tip(name, pr.loads[-1], pr.dxs[0], nu=0.3)
        assert abs(r["dz"]) < 1e-12 * abs(r["dv"])


# -- (a) truss at nu = 0: exact ------------------------------------------------

def test_truss_nu0_table_is_the_exact_1d_svk_bar():
    truss = fe.PROBLEMS["truss"]
    model = theory.Truss()
    for load in truss.loads:
        lam = exact_truss_stretch(load, truss)
        assert lam == pytest.approx(model.stretch(load, "pk1"), rel=1e-12)
        for dx in truss.dxs:
            for plane in ("stress", "strain"):
                r = fe.tip("truss", load, dx, nu=0.0, plane=plane)
                exact = (lam - 1.0) * (truss.L - 0.5 * dx)
                assert r["dh"] == pytest.approx(exact, rel=1e-8, abs=0.0)
                assert abs(r["dv"]) < 1e-12 * abs(exact)


def test_truss_nu0_fresh_solve_is_exact():
    truss = fe.PROBLEMS["truss"]
    mesh = fe.make_mesh(truss, 0)
    res = fe.solve_case(truss, [7000.0, -7000.0], 0.0, "stress", mesh, dxs=[0.002, 0.01])
    for load in (7000.0, -7000.0):
        lam = exact_truss_stretch(load, truss)
        for j, dx in enumerate((0.002, 0.01)):
            exact = (lam - 1.0) * (truss.L - 0.5 * dx)
            assert res[load][j][0] == pytest.approx(exact, rel=1e-10, abs=0.0)


# -- (b) beam against beam theory and a second FE code --------------------------

def _face_mean(mesh_level: int, load: float, nu: float):
    beam = fe.PROBLEMS["beam"]
    mesh = fe.make_mesh(beam, mesh_level)
    res = fe.solve_case(beam, [load], nu, "stress", mesh, dxs=[0.002],
                        x_columns={"face": (beam.L, beam.H / 400)})
    return res["face"][load], res[load][0]


def test_beam_small_load_against_reissner_shear_beam():
    """Mean displacement of the loaded face x = L at -10 N, nu = 0, against
    Reissner's geometrically exact shear beam (Cowper's kappa = 5/6).

    Converged (level 3), the two agree to 1.1e-5 in dv (face mean -2.011815
    mm, beam -2.011794 mm) and 8e-5 in dh: the beam misses only the clamp's
    warping restraint and the end load's Saint-Venant zone, O((H/L)^3) =
    1e-3 times a small coefficient.  The level-1 mesh used here is itself
    within ~1.5e-5 (Richardson), so 1e-4 (dv) and 1e-3 (dh, a second-order
    quantity 6e-3 of dv) are strict bounds.  (At nu = 0.3 the continuum is
    0.16 % stiffer than this beam with Cowper's coefficient: the clamp
    restrains the Poisson contraction; not asserted.)"""
    face, _ = _face_mean(1, -10.0, 0.0)
    dh, dv = theory.shear_beam_tip(theory.Beam(), -10.0, nu=0.0)
    assert face[1] == pytest.approx(dv, rel=1e-4)
    assert face[0] == pytest.approx(dh, rel=1e-3)
    # and against the elastica (no shear): the continuum is 0.60 % softer,
    # the shear compliance 3 E I/(kappa G A L^2) = 0.6 (H/L)^2
    _, dv_el = theory.beam_tip(theory.Beam(), -10.0)
    assert face[1] / dv_el - 1.0 == pytest.approx(0.006, abs=2e-4)


@pytest.mark.slow
def test_beam_linear_limit_against_linear_q9_code():
    """Linear limit (load 1e-6 of -10 N, scaled) of the mean uy over the line
    x = L - 1 mm, against studies/beam_error/fe_continuum.py (an independent
    linear Q9 code on a uniform 400 x 8 mesh, exact line mean; its 800 x 16
    mesh moves it by 2.5e-7).  Level 2 here is within ~1e-6 of converged
    (level 3 agrees with fe_continuum to 2.3e-7), so 5e-6 is strict."""
    if not (STUDIES / "fe_continuum.py").exists():
        pytest.skip("studies/beam_error/fe_continuum.py not in this checkout")
    sys.path.insert(0, str(STUDIES))
    try:
        import fe_continuum
    finally:
        sys.path.remove(str(STUDIES))
    beam = fe.PROBLEMS["beam"]
    s = beam.L - 0.001
    other = fe_continuum.solve_fe(400, 8, F=-10.0, s_list=[s])[0]
    mesh = fe.make_mesh(beam, 2)
    scale = 1e-6
    res = fe.solve_case(beam, [-10.0 * scale], 0.0, "stress", mesh, dxs=[0.002],
                        x_columns={"line": (s, beam.H / 400)})
    mine = res["line"][-10.0 * scale][1] / scale
    assert mine == pytest.approx(other, rel=5e-6)


# -- (c) patch tests --------------------------------------------------------------

def _distorted(mesh, amount, rng):
    """Move the interior vertices of a tensor mesh by up to `amount` of the
    smallest spacing (bilinear/trilinear elements stay valid)."""
    p = mesh.p.copy()
    lo, hi = p.min(axis=1, keepdims=True), p.max(axis=1, keepdims=True)
    interior = np.all((p > lo + 1e-12) & (p < hi - 1e-12), axis=0)
    h = min(np.diff(np.unique(p[i])).min() for i in range(p.shape[0]))
    p[:, interior] += amount * h * rng.uniform(-1, 1, size=(p.shape[0], interior.sum()))
    return type(mesh)(p, mesh.t)


@pytest.mark.parametrize("dim", [2, 3])
def test_uniform_stretch_patch_test(dim):
    """A homogeneous SVK stretch F0 = diag(l1, l2(, l3)) with traction-free
    lateral faces: rollers on x = 0, y = 0 (z = 0), the dead traction P11 on
    x = L.  Any mesh (here a distorted one) reproduces u = (F0 - I) X."""
    rng = np.random.default_rng(1)
    E, nu = 2.0e9, 0.3
    plane = "stress" if dim == 2 else "3d"
    lam, mu = fe.lame(E, nu, plane)
    if dim == 2:
        mesh = skfem.MeshQuad.init_tensor(np.linspace(0, 0.2, 5), np.linspace(0, 0.05, 4))
    else:
        mesh = skfem.MeshHex.init_tensor(np.linspace(0, 0.2, 4), np.linspace(0, 0.05, 3),
                                         np.linspace(0, 0.04, 3))
    mesh = _distorted(mesh, 0.2, rng)
    l1 = 1.06
    e11 = 0.5 * (l1 ** 2 - 1.0)
    # lateral S = 0: lambda (e11 + (dim - 1) e) + 2 mu e = 0
    e = -lam * e11 / (lam * (dim - 1) + 2.0 * mu)
    lt = math.sqrt(1.0 + 2.0 * e)
    p11 = l1 * (lam * (e11 + (dim - 1) * e) + 2.0 * mu * e11)
    area = 0.05 * (1e-3 if dim == 2 else 0.04)
    rollers = [(lambda x, i=i: np.isclose(x[i], 0.0), [i]) for i in range(dim)]
    solver = fe.SVKSolver(mesh, lam, mu, thickness=1e-3 if dim == 2 else 1.0,
                          dirichlet=rollers)
    force = np.zeros(dim)
    force[0] = p11 * area
    f = solver.face_load(0.2, force)
    u, _, rel = solver.newton(np.zeros(solver.N), f)
    X = solver.basis.doflocs
    expect = np.vstack([(l1 - 1.0) * X[0]] + [(lt - 1.0) * X[i] for i in range(1, dim)])
    got = u.reshape(-1, dim).T
    assert np.abs(got - expect).max() < 1e-10 * np.abs(expect).max()
    # and the tip column of any dx reads it
    m = solver.column_probe(np.array([[0.15, 0.15], [0.01, 0.03]] +
                                     ([[0.01, 0.02]] if dim == 3 else [])))
    assert m @ u[0::dim] == pytest.approx((l1 - 1.0) * 0.15, rel=1e-10)


def test_prescribed_homogeneous_deformation_with_shear():
    """All boundary DOFs prescribed by a general F0 (stretch + shear): the
    interior of a distorted mesh follows exactly."""
    rng = np.random.default_rng(2)
    mesh = _distorted(skfem.MeshQuad.init_tensor(np.linspace(0, 1, 5), np.linspace(0, 1, 5)),
                      0.25, rng)
    lam, mu = fe.lame(1.0, 0.3, "strain")
    F0 = np.array([[1.1, 0.2], [-0.05, 0.95]])
    def boundary(x):
        return (np.isclose(x[0], 0.0) | np.isclose(x[0], 1.0)
                | np.isclose(x[1], 0.0) | np.isclose(x[1], 1.0))

    solver = fe.SVKSolver(mesh, lam, mu, dirichlet=[(boundary, [0, 1])])
    X = solver.basis.doflocs
    exact = ((F0 - np.eye(2)) @ X).T.ravel()
    u0 = np.where(solver.fixed, exact, 0.0)
    u, _, _ = solver.newton(u0, np.zeros(solver.N))
    assert np.abs(u - exact).max() < 1e-10


# -- (d) recomputation and 3D consistency -------------------------------------------

@pytest.mark.slow
def test_coarse_recomputation_reproduces_a_stored_beam_entry():
    """beam, nu = 0.3, plane stress, -75 N, dx = 2 mm on the family's two
    coarsest levels: the first reproduces the table's own value for it, and
    the second is within the stored error estimate plus its own error
    (bounded by |second - first|, i.e. a convergence order >= 1)."""
    beam = fe.PROBLEMS["beam"]
    load, dx, nu = -75.0, 0.002, 0.3
    stored = next(e for e in fe._load_table()["problems"]["beam"]["entries"]
                  if e["load"] == load and e["dx"] == dx and e["nu"] == nu
                  and e["plane"] == "stress")
    values = []
    for level in beam.levels[:2]:
        res = fe.solve_case(beam, [load], nu, "stress", fe.make_mesh(beam, level), dxs=[dx])
        values.append(res[load][0])
    c0, c1 = values
    assert c0 == pytest.approx(stored["levels"][0], rel=1e-8)
    for i, c in enumerate(("dh", "dv")):
        own = abs(c1[i] - c0[i])
        assert abs(c1[i] - stored[c]) <= stored["err_" + c] + own


@pytest.mark.slow
def test_half_z_model_equals_full_model():
    pr = fe.PROBLEMS["beam3d"]
    full = fe.solve_case(pr, [-200.0], 0.3, "3d", fe.make_mesh(pr, 0, half_z=False),
                         dxs=[0.004, 0.005])
    half = fe.solve_case(pr, [-200.0], 0.3, "3d", fe.make_mesh(pr, 0, half_z=True),
                         dxs=[0.004, 0.005])
    assert full["info"]["half_z"] is False and half["info"]["half_z"] is True
    np.testing.assert_allclose(half[-200.0][:, :2], full[-200.0][:, :2], rtol=1e-9)
    assert np.abs(full[-200.0][:, 2]).max() < 1e-9 * np.abs(full[-200.0][:, 1]).max()


def test_3d_nu0_equals_2d_plane_stress():
    """With nu = 0 (lambda = 0) the 3D beam is exactly the 2D one of thickness
    W (u independent of z, u_z = 0), and beam3d_short is beam3d scaled by
    1/2 (loads by 1/4): the 3D table must agree with the (much finer) 2D
    table within the two stated errors."""
    b2, b3 = fe.PROBLEMS["beam"], fe.PROBLEMS["beam3d"]
    ratio = b3.W / b2.t
    for load3, short_load in ((-200.0, -50.0), (-1500.0, None), (-5000.0, -1250.0)):
        for dx in b3.dxs:
            r2 = fe.tip("beam", load3 / ratio, dx, nu=0.0)
            r3 = fe.tip("beam3d", load3, dx, nu=0.0)
            for c in ("dh", "dv"):
                assert abs(r3[c] - r2[c]) <= r3["err_" + c] + r2["err_" + c], (load3, dx, c)
            if short_load is not None and any(
                    math.isclose(dx / 2, d) for d in fe.PROBLEMS["beam3d_short"].dxs):
                rs = fe.tip("beam3d_short", short_load, dx / 2, nu=0.0)
                for c in ("dh", "dv"):
                    assert abs(2 * rs[c] - r2[c]) <= 2 * rs["err_" + c] + r2["err_" + c]


def test_uniform_meshes_converge_at_the_clamp_corner_bound():
    """Q2 elements on uniform meshes (the particles' resolution) against the
    graded reference: exact to 1e-5 at nu = 0, where the clamp's corners
    are regular, and at nu = 0.3 at about Williams' 2 lambda = 1.52, not 2."""
    problem = fe.PROBLEMS["beam"]
    _, q_max = theory.clamp_corner_order(0.3, "stress")
    for nu in (0.0, 0.3):
        errs = []
        for dx in (0.002, 0.001):
            tips = fe.solve_case(problem, [-10.0], nu, "stress", fe.uniform_mesh(problem, dx),
                                 dxs=(dx,))
            errs.append(tips[-10.0][0][1] / fe.tip("beam", -10.0, dx, nu, "stress")["dv"] - 1)
        if nu == 0.0:
            assert max(abs(e) for e in errs) < 1e-5
        else:
            assert min(abs(e) for e in errs) > 1e-5      # the corners are felt
            q = math.log(errs[0] / errs[1]) / math.log(2.0)
            assert q == pytest.approx(q_max, abs=0.1)
    with pytest.raises(ValueError, match="2D only"):
        fe.uniform_mesh(fe.PROBLEMS["beam3d"], 0.002)


# -- (e) the beam under its own weight (body force rho g) ----------------------------

GRAVITY = "beam_gravity"


def _gravity_solve(level: int, gys, nu: float = 0.0, plane: str = "stress", axis=()):
    """Fresh solve of the gravity beam on the level-th mesh of its family, for
    the linear-regime g's `gys` (one load step each: Newton converges in 2 or
    3 iterations): {gy: {"column": (ndx, 2), "end": (2,), X: (2,) for the
    axis points (X, H/2) in `axis`}}."""
    pr = fe.GRAVITY_PROBLEMS[GRAVITY]
    points = {"end": (pr.L, 0.5 * pr.H)}
    points.update({X: (X, 0.5 * pr.H) for X in axis})
    res = fe.solve_case(pr, [-g for g in gys], nu, plane, fe.make_mesh(pr, level),
                        points=points, max_step=max(gys))
    return {g: {"column": res[-g], **{k: res[k][-g] for k in points}} for g in gys}


@functools.lru_cache(maxsize=None)
def _gravity_linear(level: int, nu: float, plane: str) -> dict:
    """Solve at g = 9.81 (linear regime) with the end point and the axis
    points X = L/4, L/2, 3L/4 (shared by the closed-form cross-checks;
    level 1: 0.3 s a case, level 2: 2 s)."""
    L = fe.GRAVITY_PROBLEMS[GRAVITY].L
    return _gravity_solve(level, (9.81,), nu=nu, plane=plane,
                          axis=(0.25 * L, 0.5 * L, 0.75 * L))[9.81]


def assert_tip_reader_covers(pr, reader) -> list:
    """Every (case, load, dx) of problem pr and its end point can be read:
    the five fields, moving down and toward the clamp, and the end-face
    centre further than the tip column (it is further out).  Returns
    (nu, plane, gy, end entry) per case and load."""
    ends = []
    for nu, plane in pr.cases:
        for load in pr.loads:
            gy = -load
            for dx in pr.dxs:
                r = reader(gy, dx, nu=nu, plane=plane)
                assert set(r) == {"dh", "dv", "error_estimate", "err_dh", "err_dv"}
                assert r["dv"] < 0.0 and r["dh"] < 0.0
            end = reader(gy, nu=nu, plane=plane, point="end")
            assert end["dv"] < reader(gy, pr.dxs[-1], nu=nu, plane=plane)["dv"]
            ends.append((nu, plane, gy, end))
    return ends


def test_gravity_table_covers_every_case():
    pr = fe.GRAVITY_PROBLEMS[GRAVITY]
    assert pr.load_kind == "gravity" and pr.rho == 1000.0
    entries = fe._load_table(fe.GRAVITY_TABLE)["problems"][GRAVITY]["entries"]
    assert len(entries) == len(pr.cases) * len(pr.loads) * (len(pr.dxs) + len(pr.points))
    assert_tip_reader_covers(pr, fe.gravity_tip)


def test_gravity_table_meets_the_convergence_target():
    """Every value (both components, columns and the end point) within 1e-6
    relative (Richardson estimate of the finest of three levels)."""
    part = fe._load_table(fe.GRAVITY_TABLE)["problems"][GRAVITY]
    for e in part["entries"]:
        assert e["error_estimate"] < 1e-6, e
        assert e["err_dv"] < 1e-6 * abs(e["dv"]) and e["err_dh"] < 1e-6 * abs(e["dh"]), e
    assert part["meta"]["load_kind"] == "gravity"


def test_gravity_tip_missing_case_names_it_and_the_command():
    with pytest.raises(KeyError) as err:
        fe.gravity_tip(20.0, 0.002, nu=0.3, plane="stress")
    msg = str(err.value)
    assert "gy=20" in msg and "dx=0.002" in msg and "nu=0.3" in msg
    assert "python -m esph.fe --write --problems beam_gravity" in msg
    with pytest.raises(KeyError, match="no entry"):
        fe.gravity_tip(9.81, nu=0.3, plane="strain", point="end")
    with pytest.raises(ValueError, match="needs dx"):
        fe.gravity_tip(9.81)


def test_gravity_table_is_linear_at_small_g():
    """dv (odd in g: the problem mirrored in y at -g) scales with g to
    O((dv/L)^2, strain^2) ~ 1e-10 between g = 1 and 9.81 m/s^2; dh (even:
    zero in linear theory, by the mirror symmetry of the column about
    mid-height and of the end point) as g^2."""
    pr = fe.GRAVITY_PROBLEMS[GRAVITY]
    for nu, plane in pr.cases:
        for dx in list(pr.dxs) + [None]:
            kw = dict(nu=nu, plane=plane, point="column" if dx else "end")
            one, g = fe.gravity_tip(1.0, dx, **kw), fe.gravity_tip(9.81, dx, **kw)
            assert g["dv"] / one["dv"] == pytest.approx(9.81, rel=1e-6)
            assert g["dh"] / one["dh"] == pytest.approx(9.81 ** 2, rel=1e-5)


def test_body_load_integrates_to_the_weight():
    """The consistent nodal body forces sum to the weight rho g L H t and
    their first moment to the weight times L/2 (the load's centroid), to
    round-off, on the graded mesh and on a distorted one (bilinear geometry:
    N_a det J is integrated exactly by the 3x3 Gauss points)."""
    pr = fe.GRAVITY_PROBLEMS[GRAVITY]
    rng = np.random.default_rng(3)
    g = np.array([0.0, -9.81])
    weight = pr.rho * g[1] * pr.L * pr.H * pr.t
    for mesh in (fe.make_mesh(pr, 0), _distorted(fe.make_mesh(pr, 0), 0.2, rng)):
        solver = fe.SVKSolver(mesh, *fe.lame(pr.E, 0.3, "stress"), thickness=pr.t)
        f = solver.body_load(pr.rho * g)
        assert np.all(f[0::2] == 0.0)
        assert f[1::2].sum() == pytest.approx(weight, rel=1e-12, abs=0.0)
        X = solver.basis.doflocs
        assert f[1::2] @ X[0] == pytest.approx(weight * pr.L / 2, rel=1e-12, abs=0.0)
        assert f[1::2] @ X[1] == pytest.approx(weight * pr.H / 2, rel=1e-12, abs=0.0)
        assert np.all(f[1::2] < 0.0)     # Q9 (unlike the 8-node serendipity): all shares > 0


def test_gravity_fresh_solve_is_linear_at_small_g():
    """A coarse solve (level 0): u_y at the end point and the tip column's
    dv at g = 9.81 are 9.81 times those at g = 1 to 1e-6 (in fact ~1e-10,
    the nonlinearity)."""
    res = _gravity_solve(0, (1.0, 9.81), nu=0.3)
    for key in ("column", "end"):
        ratio = np.asarray(res[9.81][key])[..., 1] / np.asarray(res[1.0][key])[..., 1]
        np.testing.assert_allclose(ratio, 9.81, rtol=1e-6)


def test_gravity_against_timoshenko_beam():
    """u_y of the end-face centre (L, H/2) at g = 9.81 (linear) against the
    Timoshenko beam (fe.gravity_beam_tip: q L^4/(8 E' I) + q L^2/(2 kappa G A),
    kappa = 5/6), an independent closed form.

    Expected discrepancy: 2D elasticity and the beam differ by the clamp's
    restraint of the section's warping and (nu > 0) of its Poisson
    contraction, and by the free end's Saint-Venant zone: O((H/L)^2)
    relative to the shear term, itself 0.8 % of the deflection.  At nu = 0
    the clamp's warping restraint is what kappa = 5/6 describes (as for the
    end-loaded beam: test_beam_small_load_against_reissner_shear_beam): the
    converged FE (table) is 2.6e-5 stiffer, the level-1 mesh here 4.3e-5,
    so 1e-4 is a strict bound that still resolves the shear term (80 times
    larger: Euler-Bernoulli alone misses 0.80 %).  With nu > 0 the clamp
    also stops the anticlastic Poisson contraction, and the continuum is
    stiffer than the beam: by 0.22 % at nu = 0.3, plane stress (0.16 % for
    the end load), and 0.96 % at nu = 0.4, plane strain (nu' = nu/(1-nu) =
    2/3); asserted within a factor of ~2.  The level-1 values are within
    4e-5 of the table's (converged) ones: 1e-4."""
    pr = fe.GRAVITY_PROBLEMS[GRAVITY]
    for nu, plane in pr.cases:
        fe_dv = _gravity_linear(1, nu, plane)["end"][1]
        beam = fe.gravity_beam_tip(pr, 9.81, nu=nu, plane=plane)
        if nu == 0.0:
            assert fe_dv == pytest.approx(beam, rel=1e-4)
            bernoulli = fe.gravity_beam_tip(pr, 9.81, nu=nu, kappa=math.inf)
            assert fe_dv / bernoulli - 1.0 == pytest.approx(0.008, abs=1e-4)
        elif plane == "stress":
            assert 1e-3 < 1.0 - fe_dv / beam < 4e-3
        else:
            assert 5e-3 < 1.0 - fe_dv / beam < 2e-2
        stored = fe.gravity_tip(9.81, nu=nu, plane=plane, point="end")["dv"]
        assert fe_dv == pytest.approx(stored, rel=1e-4)


def _curvature_check(level: int, rel: float):
    pr = fe.GRAVITY_PROBLEMS[GRAVITY]
    X = (0.25 * pr.L, 0.5 * pr.L, 0.75 * pr.L)
    for nu, plane in pr.cases:
        res = _gravity_linear(level, nu, plane)
        fe_d2 = res[X[0]][1] - 2 * res[X[1]][1] + res[X[2]][1]
        exact = fe.gravity_elasticity_axis(pr, 9.81, np.array(X), nu=nu, plane=plane)
        ex_d2 = exact[0] - 2 * exact[1] + exact[2]
        assert fe_d2 == pytest.approx(ex_d2, rel=rel), (nu, plane)
        bounds = [fe.gravity_elasticity_axis(pr, 9.81, pr.L, nu=nu, plane=plane, clamp=c)
                  for c in ("axis", "section")]
        assert min(bounds) < res["end"][1] < max(bounds)


def test_gravity_curvature_against_plane_elasticity():
    """The exact plane-elasticity solution of the self-weight cantilever
    (polynomial, fe.gravity_elasticity_axis) fixes the axis' u_y up to a
    rigid motion set by the clamp; away from both ends (the clamp's and the
    free end's Saint-Venant zones decay over ~H) its second difference
    u(L/4) - 2 u(L/2) + u(3L/4) is exact, including the 2D terms beyond
    Euler-Bernoulli (1.5 % of it).  The FE converges to it at order 4 (5e-4,
    4e-5, 2.6e-6 relative on levels 0, 1, 2): 1e-4 on level 1 checks those
    terms to 1 % of themselves, for plane stress and plane strain (level 2
    to 1e-5: the slow test below).  And the fully clamped end lies between
    the polynomial's two weak clamps (axis direction fixed / section
    element fixed)."""
    _curvature_check(1, 1e-4)


@pytest.mark.slow
def test_gravity_level2_closes_on_the_closed_form_and_the_table():
    """Level 2 (~5 s): the second difference within 1e-5 of the exact one
    (its FE error 2.6e-6), the end point within 1e-5 of the table (actual
    1.1e-6 to 3.6e-6)."""
    _curvature_check(2, 1e-5)
    for nu, plane in fe.GRAVITY_PROBLEMS[GRAVITY].cases:
        stored = fe.gravity_tip(9.81, nu=nu, plane=plane, point="end")["dv"]
        assert _gravity_linear(2, nu, plane)["end"][1] == pytest.approx(stored, rel=1e-5)


def assert_first_level_matches(res, entries, pr, nu, plane, loads) -> int:
    """Each stored entry of (nu, plane) and a load in loads against a fresh
    solve `res` on the table's first mesh level: equal to 1e-8, and within
    40 times the last two levels' spread of the stored value.  Returns how
    many entries were compared."""
    n = 0
    for e in entries:
        if e["nu"] != nu or e["plane"] != plane or e["load"] not in loads:
            continue
        if e.get("point"):
            mine = res[e["point"]][e["load"]]
        else:
            mine = res[e["load"]][list(pr.dxs).index(e["dx"])]
        np.testing.assert_allclose(mine, e["levels"][0], rtol=1e-8)
        spread = np.abs(np.subtract(e["levels"][-1], e["levels"][-2]))
        assert np.all(np.abs(mine - [e["dh"], e["dv"]]) <= 40 * spread), e
        n += 1
    return n


def test_gravity_coarse_recomputation_reproduces_the_table():
    """nu = 0.4 plane strain on the family's coarsest level, along the
    table's whole load path (to the geometrically nonlinear 6e4 m/s^2):
    the table's own level-1 values, and the stored (finest) ones within
    the level-1 error as the stored levels predict it (|level 1 - stored|
    <= 40 x the spread of the last two levels: 2^p + 1 + ... for orders p
    up to 5)."""
    pr = fe.GRAVITY_PROBLEMS[GRAVITY]
    nu, plane = 0.4, "strain"
    res = fe.solve_case(pr, pr.loads, nu, plane, fe.make_mesh(pr, pr.levels[0]),
                        points={p[0]: p[1:] for p in pr.points})
    entries = fe._load_table(fe.GRAVITY_TABLE)["problems"][GRAVITY]["entries"]
    assert assert_first_level_matches(res, entries, pr, nu, plane, pr.loads) > 0


# -- (f) the beam clamped to a rigid cylinder, under its own weight -------------------

CYLINDER = "beam_cylinder"


def _cylinder_solver(pr, level: int, intorder: int = 5):
    mesh = fe.make_mesh(pr, level)
    lam, mu = fe.lame(pr.E, 0.4, "strain")
    return fe.SVKSolver(mesh, lam, mu, thickness=pr.t, intorder=intorder,
                        dirichlet=[(fe.arc_clamp_facets(pr, mesh), range(2))],
                        mapping=fe.arc_mapping(pr, mesh))


def test_cylinder_mapped_mesh_has_the_exact_domain():
    """The mapped elements' area is the exact L H + (area between the arc and
    x = 0) to < 1e-9 (level 1: 1.6e-10, the 3x3 Gauss rule's h^6 error on
    the sqrt; with 8x8 points at level 0 round-off), the clamped DOFs lie
    on the circle, one arc facet per element row, and the mapped mesh
    with R -> infinity is the straight beam's."""
    import dataclasses

    pr = fe.CYLINDER_PROBLEMS[CYLINDER]
    R, c = pr.clamp_radius, 0.5 * pr.H
    exact = fe.cylinder_exact_area(pr)
    assert exact == pytest.approx(pr.L * pr.H + 2.0 * c * R - c * math.sqrt(R * R - c * c)
                                  - R * R * math.asin(c / R), rel=1e-15)
    assert fe.arc_x(pr, 0.0) == pytest.approx(-2.679491924e-3, rel=1e-9)
    solver = _cylinder_solver(pr, 1)
    assert abs(solver.w.sum() / pr.t / exact - 1.0) < 1e-9
    assert abs(_cylinder_solver(pr, 0, intorder=15).w.sum() / pr.t / exact - 1.0) < 1e-13
    X = solver.basis.doflocs[:, solver.fixed[::2]]
    np.testing.assert_allclose(np.hypot(X[0] + R, X[1] - c), R, rtol=1e-13)
    mesh = fe.make_mesh(pr, 1)
    ny = np.unique(mesh.p[1]).size - 1
    assert fe.arc_clamp_facets(pr, mesh).size == ny
    assert solver.fixed.sum() == 2 * (2 * ny + 1)
    # the map's inverse, and the straight limit
    P = fe.arc_map(pr, np.array([[0.0, 0.1, 0.2], [0.0, 0.005, 0.02]]))
    np.testing.assert_allclose(fe.arc_unmap(pr, P), [[0.0, 0.1, 0.2], [0.0, 0.005, 0.02]],
                               atol=1e-17)
    flat = dataclasses.replace(pr, clamp_radius=1e12)
    straight = fe.make_mesh(fe.GRAVITY_PROBLEMS[GRAVITY], 1)
    np.testing.assert_allclose(fe.make_mesh(flat, 1).p, straight.p, atol=1e-14)
    assert fe.cylinder_exact_area(flat) == pytest.approx(pr.L * pr.H, rel=1e-14)


def test_cylinder_corner_angle_and_exponents():
    """The arc meets y = 0 (and H) at 60 degrees (its tangent there:
    dx/dy = tan 30 deg); the clamped-free wedge of 60 degrees is less
    singular than the straight clamp's 90: lambda = 0.869 (nu = 0.4 plane
    strain; 0.650 at 90) and 1.258 (nu = 0 plane stress; 1 at 90)."""
    pr = fe.CYLINDER_PROBLEMS[CYLINDER]
    assert fe.arc_x_dy(pr, 0.0) == pytest.approx(math.tan(math.radians(30.0)), rel=1e-14)
    angle, lam, order = fe.cylinder_corner(pr, 0.4, "strain")
    assert math.degrees(angle) == pytest.approx(60.0, rel=1e-14)
    assert lam == pytest.approx(0.8694, abs=1e-4) and order == 2.0 * lam
    assert lam > theory.clamp_corner_order(0.4, "strain")[0]
    _, lam0, _ = fe.cylinder_corner(pr, 0.0, "stress")
    assert lam0 == pytest.approx(1.2585, abs=1e-4)


def test_cylinder_large_radius_reproduces_the_straight_clamp():
    """R = 1e6 m (the arc bulges c^2/(2R) = 5e-11 m beyond x = 0): nu = 0.4
    plane strain on level 1 along the whole load path reproduces the
    straight-clamp table's (fe_bodyforce.json, beam_gravity) own level-1
    values to 1e-8 (the difference goes as 1/R: 7.6e-4 m/R relative in dv,
    1.3e-3 m/R in dh; observed 7.6e-10 and 1.3e-9 here) and its stored
    finest values within the level-1 error the stored levels predict."""
    import dataclasses

    pr = dataclasses.replace(fe.CYLINDER_PROBLEMS[CYLINDER], clamp_radius=1.0e6)
    nu, plane = 0.4, "strain"
    res = fe.solve_case(pr, pr.loads, nu, plane, fe.make_mesh(pr, 1),
                        points={p[0]: p[1:] for p in pr.points})
    entries = fe._load_table(fe.GRAVITY_TABLE)["problems"][GRAVITY]["entries"]
    n = assert_first_level_matches(res, entries, pr, nu, plane, pr.loads)
    assert n == len(pr.loads) * (len(pr.dxs) + len(pr.points))


def _cylinder_part():
    if not fe.CYLINDER_TABLE.exists():
        pytest.skip(f"no cylinder table {fe.CYLINDER_TABLE} (make it with: cd python && "
                    f"{fe.REGENERATE} --problems {CYLINDER})")
    return fe._load_table(fe.CYLINDER_TABLE)["problems"][CYLINDER]


# relative convergence targets per case: nu = 0.4 plane strain on levels 2-4
# reaches 8.9e-8, nu = 0 plane stress on levels 1-3 9.4e-7
CYLINDER_TARGET = {(0.4, "strain"): 1e-6, (0.0, "stress"): 1e-6}


def test_cylinder_table_covers_every_case_and_meets_the_target():
    """Every (nu, plane, g, dx | end) entry, readable by cylinder_tip, with
    every value within its case's target (CYLINDER_TARGET, Richardson
    estimate relative)."""
    part = _cylinder_part()
    pr = fe.CYLINDER_PROBLEMS[CYLINDER]
    assert len(part["entries"]) == len(pr.cases) * len(pr.loads) * (len(pr.dxs)
                                                                      + len(pr.points))
    assert part["meta"]["load_kind"] == "gravity"
    for e in part["entries"]:
        tol = CYLINDER_TARGET[(e["nu"], e["plane"])]
        assert e["error_estimate"] < tol, e
        assert e["err_dv"] < tol * abs(e["dv"]) and e["err_dh"] < tol * abs(e["dh"]), e
    for nu, plane, gy, end in assert_tip_reader_covers(pr, fe.cylinder_tip):
            # the cylinder's arc clamps the beam less far out than x = 0 at the
            # corners: it deflects more than the straight-clamp beam
            assert end["dv"] < fe.gravity_tip(gy, nu=nu, plane=plane, point="end")["dv"]


def test_cylinder_tip_missing_case_names_it_and_the_command():
    _cylinder_part()
    with pytest.raises(KeyError) as err:
        fe.cylinder_tip(20.0, 0.002)
    msg = str(err.value)
    assert "gy=20" in msg and "dx=0.002" in msg and "nu=0.4" in msg
    assert "python -m esph.fe --write --problems beam_cylinder" in msg
    with pytest.raises(ValueError, match="needs dx"):
        fe.cylinder_tip(9.81)


def test_cylinder_cli_knows_the_problem(capsys):
    from esph.fe.__main__ import main
    assert fe.table_path(CYLINDER) == fe.CYLINDER_TABLE
    assert fe.problem_by_name(CYLINDER).clamp_radius == 0.02
    with pytest.raises(SystemExit):
        main(["--problems", "beam_cylindre"])
    assert "beam_cylinder" in capsys.readouterr().err
    if fe.CYLINDER_TABLE.exists():
        assert main(["--problems", CYLINDER]) == 0
        assert "beam_cylinder 16 entries" in capsys.readouterr().out


def test_cylinder_coarse_recomputation_reproduces_the_table():
    """nu = 0 plane stress (computed on levels 1-3) on level 1 along the
    whole load path: the table's own level-1 values (to 1e-8) and its
    finest values within the level-1 error the stored levels predict."""
    part = _cylinder_part()
    pr = fe.CYLINDER_PROBLEMS[CYLINDER]
    nu, plane = 0.0, "stress"
    assert (nu, plane) not in dict(pr.case_levels)
    res = fe.solve_case(pr, pr.loads, nu, plane, fe.make_mesh(pr, pr.levels[0]),
                        points={p[0]: p[1:] for p in pr.points})
    for e in part["entries"]:
        if e["nu"] != nu or e["plane"] != plane:
            continue
        mine = (res[e["point"]][e["load"]] if e.get("point")
                else res[e["load"]][list(pr.dxs).index(e["dx"])])
        np.testing.assert_allclose(mine, e["levels"][0], rtol=1e-8)
        spread = np.abs(np.subtract(e["levels"][-1], e["levels"][-2]))
        assert np.all(np.abs(mine - [e["dh"], e["dv"]]) <= 40 * spread), e
