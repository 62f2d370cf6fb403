"""Two identical elastic spheres colliding head on in 3d, with fix
sph/contact between them (examples/spheres3d/in.spheres3d): run the example
and set its contact duration and peak force beside Hertz's impact theory
(theory.hertz_impact), with the balances a collision must keep (momentum,
energy, mirror symmetry) and its throughput."""
from __future__ import annotations

import math
import tempfile
from dataclasses import asdict, dataclass
from pathlib import Path

from . import theory
from .paths import EXAMPLES
from .report import command_line, print_head, write_rows
from .runner import run_mpi

SPHERES3D = EXAMPLES / "spheres3d" / "in.spheres3d"


@dataclass
class SpheresCase:
    nr: float = 6                 # particles per radius, R/dx
    v: float = 20.0               # speed of each sphere toward the other, m/s
    R: float = 0.05               # sphere radius, m
    E: float = 20.0e9             # Pa
    nu: float = 0.3
    rho: float = 1000.0           # kg/m^3
    gap: float = 0.25             # surface gap at the start, in dx
    volumes: str = "exact"        # set_sph_volumes lattice, or cells (plain dx^3)
    stress: str = "pk1"           # icb stress measure (corotated: the paper's)
    damping: float = 0.0          # contact damping ratio
    every: int = 10               # steps between time-series rows

    @property
    def dx(self) -> float:
        return self.R / self.nr

    @property
    def tag(self) -> str:
        return f"nr{self.nr:g}_v{self.v:g}_{self.volumes}_{self.stress}"

    def variables(self, outdir: Path | None = None) -> dict:
        out = {"R": self.R, "nr": f"{self.nr:g}", "v": self.v, "E": f"{self.E:g}", "nu": self.nu,
               "rho": self.rho, "gap": self.gap, "volumes": self.volumes, "stress": self.stress,
               "damping": self.damping, "every": self.every, "tag": self.tag}
        if outdir is not None:
            out["outdir"] = str(outdir)
        return out

    def hertz(self, mass: float) -> theory.Impact:
        """Hertz's answer for two spheres of radius R and the mass the
        particles carry (the lattice sphere's volume is within a few per
        cent of 4 pi R^3/3), approaching at 2 v."""
        return theory.hertz_impact(self.R, self.E, self.nu, mass, 2.0 * self.v)

    def facet_contact(self, mass: float, facet: int) -> theory.Impact:
        """The contact of the two flat polar facets of `facet` particles
        each, as flat punches on half-spaces in series with the contact
        springs of fix sph/contact (k = dx K/2 per pair, K = E/(3 (1 - 2 nu))):
        what the lattice spheres do while the approach is small against dx."""
        bulk = self.E / (3.0 * (1.0 - 2.0 * self.nu))
        return theory.flat_contact_impact(facet * self.dx ** 2, self.E, self.nu, mass,
                                          2.0 * self.v, facet * self.dx * bulk / 2.0)


@dataclass
class SpheresResult:
    case: SpheresCase
    nprocs: int
    atoms: int
    steps: int
    wall: float                   # s, the whole mpirun
    loop: float                   # s, LAMMPS's loop time of all runs
    dt: float                     # s
    mass: float                   # kg, one sphere
    contact_first: float          # s, first step in contact (from the start)
    contact_duration: float       # s, first to last step with a contact force
    force_max: float              # N, largest sum of the contact pair forces
    restitution: float            # relative centroid velocity after separation / 2 v
    separated: bool               # the spheres came apart before tmax
    recontact: bool               # they touched again after coming apart
    momentum: float               # |total momentum| at the end / (2 m v)
    momentum_error: float         # largest |total momentum| over the run / (2 m v)
    energy_drift: float           # (E_end - E0)/E0, E = kinetic + strain + contact
    energy_error: float           # largest |E - E0|/E0 over the run
    mirror_error: float           # largest |centroid 1 - mirror of centroid 2| / dx
    failed: bool
    hertz_duration: float         # s
    hertz_force: float            # N
    hertz_approach: float         # m, Hertz's largest approach of the centres
    facet: int                    # particles in each sphere's flat polar facet
    facet_duration: float         # s, flat facets as punches (SpheresCase.facet_contact)
    facet_force: float            # N
    command: str = ""

    @property
    def duration_error(self) -> float:
        return self.contact_duration / self.hertz_duration - 1.0

    @property
    def force_error(self) -> float:
        return self.force_max / self.hertz_force - 1.0

    @property
    def facet_duration_error(self) -> float:
        return self.contact_duration / self.facet_duration - 1.0

    @property
    def throughput(self) -> float:
        """Particle-steps per second of LAMMPS's loop time (all ranks)."""
        return self.atoms * self.steps / self.loop if self.loop > 0 else math.nan

    def row(self) -> dict:
        out = {k: v for k, v in asdict(self).items() if k != "case"}
        out.update(asdict(self.case))
        out.update(dx=self.case.dx, duration_error=self.duration_error,
                   force_error=self.force_error, facet_duration_error=self.facet_duration_error,
                   throughput=self.throughput)
        return out


def run_spheres(case: SpheresCase, nprocs: int = 1, outdir: Path | None = None,
                timeout: float = 1800) -> SpheresResult:
    """Run one collision under `mpirun -np nprocs` and set it beside Hertz.
    The time series goes to outdir (default: a throwaway folder)."""
    with tempfile.TemporaryDirectory(prefix="esph-spheres3d-") as tmp:
        folder = Path(outdir).resolve() if outdir else Path(tmp)
        folder.mkdir(parents=True, exist_ok=True)
        variables = case.variables(folder)
        out = run_mpi(SPHERES3D, variables, nprocs, timeout=timeout)
    v = out.variables
    mass = v["mass"]
    hertz = case.hertz(mass)
    facet = case.facet_contact(mass, int(v["facet"]))
    pscale = 2.0 * mass * case.v
    return SpheresResult(
        case=case, nprocs=nprocs, atoms=int(v["atoms"]), steps=int(v["steps"]), wall=out.wall,
        loop=v.get("loop_total", math.nan), dt=v["dt"], mass=mass,
        contact_first=v["contact_first"], contact_duration=v["contact_duration"],
        force_max=v["fmax"], restitution=v["restitution"], separated=v["separated"] > 0.5,
        recontact=v["recontact"] > 0.5,
        momentum=math.sqrt(v["px"] ** 2 + v["py"] ** 2 + v["pz"] ** 2) / pscale,
        momentum_error=v["momentum_error"], energy_drift=v["energy_drift"],
        energy_error=v["energy_error"], mirror_error=v["mirror_error"],
        failed=v["failed"] > 0.5, hertz_duration=hertz.duration, hertz_force=hertz.force_max,
        hertz_approach=hertz.approach_max, facet=int(v["facet"]), facet_duration=facet.duration,
        facet_force=facet.force_max,
        command=command_line(SPHERES3D, case.variables(), nprocs))


HEAD = (f"{'R/dx':>4} {'v':>5} {'atoms':>6} {'ranks':>5} {'steps':>6} {'t_c[us]':>8} "
        f"{'Hertz':>8} {'err':>7} {'facet':>5} {'punch':>7} {'err':>6} {'F_max[kN]':>9} "
        f"{'Hertz':>8} {'err':>7} {'e':>6} {'dE/E0':>8} {'|p|':>8} {'mirror':>8} "
        f"{'wall[s]':>7} {'Mp-st/s':>7}")


def print_result(r: SpheresResult) -> None:
    flag = "" if r.separated and not r.recontact and not r.failed else (
        " FAILED" if r.failed else " (still in contact)" if not r.separated else " (recontact)")
    print(f"{r.case.nr:4g} {r.case.v:5g} {r.atoms:6d} {r.nprocs:5d} {r.steps:6d} "
          f"{r.contact_duration * 1e6:8.2f} {r.hertz_duration * 1e6:8.2f} "
          f"{100 * r.duration_error:+6.1f}% {r.facet:5d} {r.facet_duration * 1e6:7.2f} "
          f"{100 * r.facet_duration_error:+5.1f}% {r.force_max / 1e3:9.2f} "
          f"{r.hertz_force / 1e3:8.2f} {100 * r.force_error:+6.1f}% {r.restitution:6.3f} "
          f"{r.energy_error:8.1e} {r.momentum_error:8.1e} {r.mirror_error:8.1e} {r.wall:7.2f} "
          f"{r.throughput / 1e6:7.3f}{flag}", flush=True)


def legend(case: SpheresCase) -> str:
    return (f"t_c = contact duration (first to last step with a contact force), F_max = largest "
            f"total contact force, each against Hertz (Johnson 1985, 11.4) for the particles' "
            f"mass; facet = particles in each sphere's flat polar facet; punch = t_c of the two "
            f"facets as flat punches on half-spaces in series with the contact springs "
            f"(theory.flat_contact_impact); e = relative centroid speed after separation / "
            f"{2 * case.v:g} m/s; dE/E0 = largest error of kinetic + strain + contact energy; "
            f"|p| = largest total momentum "
            f"/ (2 m v); mirror = largest distance of centroid 1 from the mirror image of "
            f"centroid 2, / dx; Mp-st/s = million particle-steps per second of LAMMPS's loop")


def run_table(nrs, v: float = 20.0, nprocs_list=(1,), out: Path | None = None,
              progress=print, **case_options) -> list[SpheresResult]:
    """The collision at each resolution (particles per radius) and rank
    count: one row each, printed as it comes; the rows as JSON and CSV in
    `out` if given."""
    base = SpheresCase(v=v, **case_options)
    hz = base.hertz(base.rho * 4.0 / 3.0 * math.pi * base.R ** 3)
    print(f"3D sphere collision (examples/spheres3d): two spheres R = {base.R * 100:g} cm, "
          f"E = {base.E / 1e9:g} GPa, nu = {base.nu:g}, rho = {base.rho:g}, {v:g} m/s each, "
          f"pair sph/icb (stress {base.stress}, volumes {base.volumes}), fix sph/contact "
          f"(contact distance dx); Hertz: largest "
          f"approach {hz.approach_max * 1e3:.2f} mm, contact radius "
          f"{hz.contact_radius / base.R:.2f} R")
    print_head(HEAD)
    results = []
    for nr in nrs:
        for nprocs in nprocs_list:
            case = SpheresCase(nr=nr, v=v, **case_options)
            progress(f"[esph] spheres3d R/dx = {nr:g}, {v:g} m/s, {nprocs} rank(s) ...")
            res = run_spheres(case, nprocs, outdir=out)
            print_result(res)
            results.append(res)
    print(legend(base))
    if out is not None:
        write_rows(Path(out) / "spheres3d.json", [r.row() for r in results])
    return results
