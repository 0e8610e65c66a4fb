// libFuzzer target for the .sadm model reader (models, raster, triangles and
// the regressor's text). Any input must either load or raise an
// anima::error, without allocating more than the text justifies (the raster
// is bounded by anima::max_raster_pixels); a loaded model saves and loads
// back.
#include <anima/core/error.hpp>
#include <anima/sadm/sadm_model.hpp>

#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using anima_fuzz::require;
    if (size > anima_fuzz::max_input) return 0;
    std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
    try {
        const auto model = anima::sadm_model<double>::load(in, "fuzz");
        require(model.grey().raster().rows * model.grey().raster().cols <= anima::max_raster_pixels);
        std::stringstream text;
        model.save(text);
        try {
            (void)anima::sadm_model<double>::load(text, "back");
        } catch (const anima::error&) {
            require(false);
        }
    } catch (const anima::error&) {
    }
    return 0;
}
