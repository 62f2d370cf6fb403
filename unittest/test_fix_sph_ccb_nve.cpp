/* ----------------------------------------------------------------------
   LAMMPS - Large-scale Atomic/Molecular Massively Parallel Simulator
   https://www.lammps.org/, Sandia National Laboratories
   LAMMPS development team: developers@lammps.org

   Copyright (2003) Sandia Corporation.  Under the terms of Contract
   DE-AC04-94AL85000 with Sandia Corporation, the U.S. Government retains
   certain rights in this software.  This software is distributed under
   the GNU General Public License.

   See the README file in the top-level LAMMPS directory.
------------------------------------------------------------------------- */

// fix sph/ccb/nve on LAMMPS's test fixture.  The YAML fix tester forces an
// lj/cut + bonds force field on its own data file, which the integrator
// of pair sph/ccb cannot run with, so these checks are written out here:
// rest stays rest, a restart continues bitwise, the state variables are
// integrated consistently with x and v, and unsupported set-ups fail.

#include "atom.h"
#include "core.h"
#include "input.h"
#include "lammps.h"
#include "utils.h"

#include "gmock/gmock.h"
#include "gtest/gtest.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <string>
#include <vector>

bool verbose = false;

using LAMMPS_NS::tagint;

namespace {

const char *BLOCK = R"(
units si
dimension 2
boundary p p p
atom_style sph/elastic
atom_modify map array
comm_modify vel yes
lattice sq 0.001 origin 0.5 0.5 0.0
region box block 0 8 0 8 -0.5 0.5
create_box 1 box
create_atoms 1 box
set group all volume 1e-9
set group all mass 1e-6
set group all mol 1
pair_style sph/ccb 0.0012 plane strain thickness 0.001 viscosity 1.0 0.5 artificial_stress 0.3 4 0.001
pair_coeff * * 1e9 0.3
fix integrate all sph/ccb/nve
timestep 2e-8
)";

// per-atom state by atom ID: x, v, rho, deviatoric stress
std::map<tagint, std::vector<double>> snapshot(LAMMPS_NS::LAMMPS *lmp)
{
    std::map<tagint, std::vector<double>> out;
    auto *atom = lmp->atom;
    for (int i = 0; i < atom->nlocal; i++) {
        std::vector<double> s(atom->x[i], atom->x[i] + 3);
        s.insert(s.end(), atom->v[i], atom->v[i] + 3);
        s.push_back(atom->rho[i]);
        s.insert(s.end(), atom->smd_stress[i], atom->smd_stress[i] + 6);
        out[atom->tag[i]] = s;
    }
    return out;
}

}    // namespace

class FixSPHCCBNVETest : public LAMMPSTest {
protected:
    void InitSystem() override
    {
        HIDE_OUTPUT([&] {
            for (const auto &line : LAMMPS_NS::utils::split_lines(BLOCK))
                if (!line.empty()) command(line);
        });
    }

    void jiggle()
    {
        HIDE_OUTPUT([&] {
            command("displace_atoms all random 5e-5 5e-5 0.0 623426 units box");
            command("velocity all create 1e17 4534624 loop geom");
        });
    }
};

TEST_F(FixSPHCCBNVETest, RestStaysRest)
{
    HIDE_OUTPUT([&] { command("run 50"); });
    auto *atom = lmp->atom;
    for (int i = 0; i < atom->nlocal; i++) {
        for (int a = 0; a < 3; a++) ASSERT_EQ(atom->v[i][a], 0.0);
        for (int s = 0; s < 6; s++) ASSERT_EQ(atom->smd_stress[i][s], 0.0);
        // a uniform lattice at its reference density keeps it
        ASSERT_DOUBLE_EQ(atom->rho[i], 1000.0);
    }
}

TEST_F(FixSPHCCBNVETest, StateMovesWithTheFlow)
{
    // a compressive velocity field: density goes up, pressure builds
    // (negative mean normal stress), momentum stays zero
    HIDE_OUTPUT([&] {
        command("variable vx atom -100.0*(x-0.004)");
        command("velocity all set v_vx 0.0 0.0 units box");
        command("run 20");
    });
    auto *atom = lmp->atom;
    double rho_mean = 0.0, px = 0.0;
    for (int i = 0; i < atom->nlocal; i++) {
        rho_mean += atom->rho[i] / atom->nlocal;
        px += atom->rmass[i] * atom->v[i][0];
    }
    EXPECT_GT(rho_mean, 1000.0);
    EXPECT_NEAR(px, 0.0, 1e-12 * 1e-6 * 0.4 * atom->nlocal);
}

TEST_F(FixSPHCCBNVETest, RestartContinuesBitwise)
{
    jiggle();
    const std::string file = "test_fix_sph_ccb_nve.restart";
    HIDE_OUTPUT([&] {
        command("run 40");
        command("write_restart " + file);
        command("run 40");
    });
    const auto uninterrupted = snapshot(lmp);
    HIDE_OUTPUT([&] {
        command("clear");
        command("read_restart " + file);
        command("fix integrate all sph/ccb/nve");
        command("run 40");
    });
    const auto continued = snapshot(lmp);
    ASSERT_EQ(continued.size(), uninterrupted.size());
    for (const auto &[tag, state] : uninterrupted) {
        const auto &other = continued.at(tag);
        for (std::size_t k = 0; k < state.size(); k++) ASSERT_EQ(other[k], state[k]) << tag;
    }
    // some stress and density history was carried through the restart
    double most = 0.0;
    for (const auto &[tag, state] : continued) most = std::max(most, std::fabs(state[7]));
    EXPECT_GT(most, 0.0);
    std::remove(file.c_str());
}

TEST_F(FixSPHCCBNVETest, UnsupportedSetups)
{
    TEST_FAILURE(".*ERROR: Fix sph/ccb/nve does not support run_style respa.*",
                 command("run_style respa 2 2"); command("run 1"););
    TEST_FAILURE(".*ERROR.*requires pair style sph/ccb.*", {
        command("run_style verlet");
        command("pair_style sph/icb 0.0012 stress pk1");
        command("pair_coeff * * 1e9 0.3");
        command("run 0");
    });
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    ::testing::InitGoogleMock(&argc, argv);
    if ((argc > 1) && (strcmp(argv[1], "-v") == 0)) verbose = true;
    int rv = RUN_ALL_TESTS();
    MPI_Finalize();
    return rv;
}
