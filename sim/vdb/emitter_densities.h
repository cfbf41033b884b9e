// Density-seeded emitters (EmitterShape::Density) get their grid here: brume_sim samples a
// DensitySampler but cannot read .vdb files itself, since only brume_vdb links OpenVDB.
#pragma once

#include "sim/preset.h"

namespace brume {

// Reads every Density emitter's density_source (sim/vdb/density_source.h) and sets its `density` sampler.
// Throws VdbError naming the emitter and the source when a grid cannot be read or holds no density.
void load_emitter_densities(Preset& preset);

}  // namespace brume
