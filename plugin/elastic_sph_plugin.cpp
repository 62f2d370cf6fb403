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

/* ----------------------------------------------------------------------
   Contributing author: ELASTIC-SPH developers
   The package as a LAMMPS plugin: `plugin load elasticsphplugin.so`, or
   loaded by itself from a folder in LAMMPS_PLUGIN_PATH.  The same sources
   as the in-tree package; this file only registers their styles.
   LAMMPS's plugin API registers pair, fix, compute and command styles;
   atom and min styles it does not, so this file adds them to the public
   creator maps of Atom and Update (they are then missing from `plugin
   list` and cannot be unloaded, and the library is linked with
   -z nodelete: `clear` closes plugins before it deletes the atom and min
   objects whose code lives here).
------------------------------------------------------------------------- */

#include "lammpsplugin.h"

#include "atom.h"
#include "error.h"
#include "force.h"
#include "lammps.h"
#include "update.h"
#include "version.h"

#include "atom_vec_sph_elastic.h"
#include "compute_sph_elastic_atom.h"
#include "compute_sph_probe.h"
#include "create_sph_mirrors.h"
#include "create_sph_twins.h"
#include "fix_sph_bodyforce.h"
#include "fix_sph_ccb_nve.h"
#include "fix_sph_contact.h"
#include "fix_sph_fluid.h"
#include "fix_sph_minimize_check.h"
#include "fix_sph_mirror.h"
#include "fix_sph_partners.h"
#include "fix_sph_rotation.h"
#include "fix_sph_traction.h"
#include "min_sph_newton.h"
#include "pair_sph_ccb.h"
#include "pair_sph_icb.h"
#include "reset_sph_reference.h"
#include "set_sph_volumes.h"

#include <mpi.h>

#include <string>

using namespace LAMMPS_NS;

// the LAMMPS version the plugin was compiled for (the test suite builds a
// twin that claims another, for the mismatch error)
#ifdef ESPH_PLUGIN_CLAIMED_VERSION
#define ESPH_BUILT_FOR ESPH_PLUGIN_CLAIMED_VERSION
#else
#define ESPH_BUILT_FOR LAMMPS_VERSION
#endif

namespace {
const char *const AUTHOR = "ELASTIC-SPH developers";

template <class T> void *new_pair(void *lmp)
{
  return new T(static_cast<LAMMPS *>(lmp));
}

template <class T> void *new_command(void *lmp)
{
  return new T(static_cast<LAMMPS *>(lmp));
}

template <class T> void *new_styled(void *lmp, int narg, char **arg)
{
  return new T(static_cast<LAMMPS *>(lmp), narg, arg);
}

template <class T> AtomVec *new_atom_vec(LAMMPS *lmp)
{
  return new T(lmp);
}

template <class T> Min *new_min(LAMMPS *lmp)
{
  return new T(lmp);
}

// the MPI library this plugin was compiled with, and the one running
std::string compiled_mpi()
{
#if defined(OPEN_MPI)
  return "Open MPI";
#elif defined(MPICH_VERSION)
  return "MPICH";
#else
  return "";
#endif
}

std::string running_mpi()
{
  char text[MPI_MAX_LIBRARY_VERSION_STRING];
  int length = 0;
  MPI_Get_library_version(text, &length);
  const std::string version(text, length);
  if (version.find("Open MPI") != std::string::npos) return "Open MPI";
  if (version.find("MPICH") != std::string::npos) return "MPICH";
  return "";
}

/* ----------------------------------------------------------------------
   a plugin compiled against other headers would use other class layouts:
   refuse it before anything is registered
------------------------------------------------------------------------- */

void check_host(LAMMPS *lmp)
{
  if (std::string(ESPH_BUILT_FOR) != lmp->version)
    lmp->error->all(FLERR,
                    "The ELASTIC-SPH plugin was built for LAMMPS version {} but is loaded "
                    "into LAMMPS version {}: build it against this LAMMPS's source tree "
                    "(plugin/README.md)",
                    ESPH_BUILT_FOR, lmp->version);
  const std::string built = compiled_mpi(), running = running_mpi();
  if (!built.empty() && !running.empty() && built != running)
    lmp->error->all(FLERR,
                    "The ELASTIC-SPH plugin was built with {} but this LAMMPS runs on {}: "
                    "build the plugin with the MPI library LAMMPS uses",
                    built, running);
  if (lmp->force->pair_map->count("sph/icb"))
    lmp->error->all(FLERR,
                    "Pair style sph/icb exists already: the ELASTIC-SPH plugin is loaded, or "
                    "the package is compiled into this LAMMPS; load the plugin once, into a "
                    "LAMMPS without the package");
}

void register_style(lammpsplugin_regfunc add, void *lmp, void *handle, const char *style,
                    const char *name, lammpsplugin_factory1 *creator1,
                    lammpsplugin_factory2 *creator2)
{
  lammpsplugin_t plugin;
  plugin.version = ESPH_BUILT_FOR;
  plugin.style = style;
  plugin.name = name;
  plugin.info = "ELASTIC-SPH: elastic solids by SPH";
  plugin.author = AUTHOR;
  if (creator1)
    plugin.creator.v1 = creator1;
  else
    plugin.creator.v2 = creator2;
  plugin.handle = handle;
  (*add)(&plugin, lmp);
}
}    // namespace

/* ---------------------------------------------------------------------- */

extern "C" void lammpsplugin_init(void *ptr, void *handle, void *regfunc)
{
  auto *lmp = static_cast<LAMMPS *>(ptr);
  auto add = (lammpsplugin_regfunc) regfunc;
  check_host(lmp);

  register_style(add, ptr, handle, "pair", "sph/icb", &new_pair<PairSPHICB>, nullptr);
  register_style(add, ptr, handle, "pair", "sph/ccb", &new_pair<PairSPHCCB>, nullptr);

  register_style(add, ptr, handle, "fix", "sph/bodyforce", nullptr, &new_styled<FixSPHBodyForce>);
  register_style(add, ptr, handle, "fix", "sph/ccb/nve", nullptr, &new_styled<FixSPHCCBNVE>);
  register_style(add, ptr, handle, "fix", "sph/contact", nullptr, &new_styled<FixSPHContact>);
  register_style(add, ptr, handle, "fix", "sph/fluid", nullptr, &new_styled<FixSPHFluid>);
  register_style(add, ptr, handle, "fix", "sph/mirror", nullptr, &new_styled<FixSPHMirror>);
  register_style(add, ptr, handle, "fix", "SPH_MINIMIZE_CHECK", nullptr,
                 &new_styled<FixSPHMinimizeCheck>);
  register_style(add, ptr, handle, "fix", "SPH_PARTNERS", nullptr, &new_styled<FixSPHPartners>);
  register_style(add, ptr, handle, "fix", "sph/rotation", nullptr, &new_styled<FixSPHRotation>);
  register_style(add, ptr, handle, "fix", "sph/traction", nullptr, &new_styled<FixSPHTraction>);

  register_style(add, ptr, handle, "compute", "sph/elastic/atom", nullptr,
                 &new_styled<ComputeSPHElasticAtom>);
  register_style(add, ptr, handle, "compute", "sph/probe", nullptr, &new_styled<ComputeSPHProbe>);

  register_style(add, ptr, handle, "command", "create_sph_mirrors", &new_command<CreateSPHMirrors>,
                 nullptr);
  register_style(add, ptr, handle, "command", "create_sph_twins", &new_command<CreateSPHTwins>,
                 nullptr);
  register_style(add, ptr, handle, "command", "reset_sph_reference",
                 &new_command<ResetSPHReference>, nullptr);
  register_style(add, ptr, handle, "command", "set_sph_volumes", &new_command<SetSPHVolumes>,
                 nullptr);

  // the two kinds the plugin API does not register (see the top)
  (*lmp->atom->avec_map)["sph/elastic"] = &new_atom_vec<AtomVecSPHElastic>;
  (*lmp->update->minimize_map)["sph/newton"] = &new_min<MinSPHNewton>;
}
