#include "sim/vdb/emitter_densities.h"

#include "sim/density_sampler.h"
#include "sim/scene_file.h"
#include "sim/vdb/density_source.h"
#include "sim/vdb/vdb_file.h"

#include <memory>
#include <stdexcept>
#include <string>

namespace brume {

void load_emitter_densities(Preset& preset) {
    for (std::size_t i = 0; i < preset.emitters.size(); ++i) {
        EmitterDesc& e = preset.emitters[i];
        if (e.shape != EmitterShape::Density) continue;
        // Messages name the emitter as the preset file does (its index) and as the user does (its name).
        // "FILE:LINE: emitter[0] ("name"): ", as the reader's own messages and a [[vdb]] volume's start.
        const std::string who = (e.defined_at.empty() ? "" : e.defined_at + ": ") + "emitter[" + std::to_string(i) +
                                "] (" + toml_text::quoted(e.name) + "): ";
        try {
            e.density = std::make_shared<const DensitySampler>(read_density_source(e.density_source),
                                                               e.density_transform);
        } catch (const VdbError& error) {
            throw VdbError(who + error.what());
        } catch (const std::invalid_argument& error) {
            // A grid whose active voxels are all 0, or a transform built in code that no file would pass.
            throw VdbError(who + density_source_label(e.density_source) + ": " + error.what());
        }
    }
}

}  // namespace brume
