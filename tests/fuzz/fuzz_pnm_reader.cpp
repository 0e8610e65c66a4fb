// libFuzzer target for the PGM/PPM reader. Any input must either decode or
// raise an anima::error, allocating no more than the file's bytes justify; a
// decoded image must match its header and write back to the same pixels.
#include <anima/core/error.hpp>
#include <anima/image/pnm.hpp>

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using anima_fuzz::require;
    if (size > anima_fuzz::max_input) return 0;
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    try {
        const auto p = anima::parse_pnm(bytes, "fuzz");
        const auto& img = p.pixels;
        require(img.width >= 1 && img.height >= 1 && (img.channels == 1 || img.channels == 3));
        const std::size_t samples = static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height) *
                                    static_cast<std::size_t>(img.channels);
        require(img.pixels.size() == samples);
        require(samples <= 2 * size + 2);  // never more samples than the bytes could hold
        for (auto v : img.pixels) require(v <= p.maxval);
        if (p.maxval == 255) {
            anima::image<unsigned char> bytes8(img.width, img.height, img.channels);
            for (std::size_t k = 0; k < samples; ++k) bytes8.pixels[k] = static_cast<unsigned char>(img.pixels[k]);
            const auto back = anima::parse_pnm(anima::format_pnm(bytes8), "back");
            require(back.pixels.pixels == img.pixels);
        }
    } catch (const anima::error&) {
    }
    return 0;
}
