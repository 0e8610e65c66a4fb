// pnm_to_image IN.pgm|IN.ppm OUT.png|OUT.jpg: the same pixels as a PNG, or
// as a JPEG of quality 95 (stb's writer), so that the command line tests can
// feed anima's PNG and JPEG reading paths images whose PGM twins they also
// have. 8-bit files only.
#include <anima/image/pnm.hpp>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#include <stb_image_write.h>

#include <cstddef>
#include <cstdio>
#include <cstring>
#include <exception>
#include <vector>

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: pnm_to_image IN.pgm OUT.png|OUT.jpg\n");
        return 2;
    }
    try {
        const anima::pnm_image in = anima::read_pnm(argv[1]);
        if (in.maxval != 255) {
            std::fprintf(stderr, "pnm_to_image: %s: maxval %d, only 255 is converted\n", argv[1], in.maxval);
            return 1;
        }
        const std::vector<unsigned char> bytes(in.pixels.pixels.begin(), in.pixels.pixels.end());
        const auto& p = in.pixels;
        const std::size_t length = std::strlen(argv[2]);
        const bool jpeg = length > 4 && std::strcmp(argv[2] + length - 4, ".jpg") == 0;
        const int written = jpeg ? stbi_write_jpg(argv[2], p.width, p.height, p.channels, bytes.data(), 95)
                                 : stbi_write_png(argv[2], p.width, p.height, p.channels, bytes.data(), p.width * p.channels);
        if (!written) {
            std::fprintf(stderr, "pnm_to_image: cannot write %s\n", argv[2]);
            return 1;
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "pnm_to_image: %s\n", e.what());
        return 1;
    }
    return 0;
}
