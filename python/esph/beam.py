"""Cantilever beam validation (paper section 3.1) through examples/beam/in.beam."""
from __future__ import annotations

from dataclasses import dataclass

from .problems import BEAM, beam_exact
from .runner import run_tip


@dataclass
class BeamCase:
    load: float = -250.0          # N
    dx: float = 0.002             # m
    nu: float = 0.0
    plane: str = "stress"
    stress: str = "pk1"
    route: str = "min"
    hourglass: float = 0.0
    gradient: str = "linear"      # linear (paper) or quadratic
    clamp: str = "fixed"          # fixed columns (paper) or mirror (fix sph/mirror)

    def variables(self) -> dict:
        return {"Fy": self.load, "dx": self.dx, "nu": self.nu, "plane": self.plane,
                "stress": self.stress, "route": self.route, "hg": self.hourglass,
                "grad": self.gradient, "clamp": self.clamp}


@dataclass
class BeamResult:
    case: BeamCase
    dh: float
    dv: float
    steps: int
    natoms: int
    wall: float

    @property
    def exact(self) -> tuple[float, float]:
        """Elastica at the tip column's material point."""
        return beam_exact(self.case.load, self.case.dx)

    @property
    def error_dv(self) -> float:
        return self.dv / self.exact[1] - 1.0

    @property
    def error_dh(self) -> float:
        return self.dh / self.exact[0] - 1.0


def run_beam(case: BeamCase, nprocs: int = 1) -> BeamResult:
    tip = run_tip(BEAM, case.variables(), nprocs)
    return BeamResult(case, tip.dh, tip.dv, tip.steps, tip.natoms, tip.wall)
