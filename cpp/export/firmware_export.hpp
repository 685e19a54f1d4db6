#pragma once
// `kiloloop export`'s C++ half: the source text of a model description and of a controller's
// settings, every double as a C99 hex float (%a: exact, never rounded). The Python half
// (python/kiloloop/firmware/) assembles the header and the manifest around these blocks.
#include <string>

#include "kiloloop/firmware/fields.hpp"
#include "kiloloop/model/model_description.hpp"

namespace kiloloop {

// `inline constexpr SegmentSpec kSegments[] = {...}; inline constexpr ModelDescription
// kDescription{...};` (names in the current namespace of the including file).
std::string description_source(const ModelDescription& description);

// `struct Settings {...}; inline constexpr Settings kSettings{};` and
// `inline <Config> make_config() {...}` setting every field of the config from kSettings.
std::string settings_source(const ComputedTorqueConfig& config);
std::string settings_source(const QuadrupedConfig& config);
std::string settings_source(const AerialConfig& config);

}  // namespace kiloloop
