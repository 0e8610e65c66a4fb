// pnm_to_png IN.pgm|IN.ppm OUT.png: the same pixels as a PNG (stb's writer),
// so that the command line tests can feed anima's PNG reading path images
// whose PGM twins they also have. 8-bit files only.
#include <anima/image/pnm.hpp>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#include <stb_image_write.h>

#include <cstdio>
#include <exception>
#include <vector>

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: pnm_to_png IN.pgm OUT.png\n");
        return 2;
    }
    try {
        const anima::pnm_image in = anima::read_pnm(argv[1]);
        if (in.maxval != 255) {
            std::fprintf(stderr, "pnm_to_png: %s: maxval %d, only 255 is converted\n", argv[1], in.maxval);
            return 1;
        }
        const std::vector<unsigned char> bytes(in.pixels.pixels.begin(), in.pixels.pixels.end());
        const auto& p = in.pixels;
        if (!stbi_write_png(argv[2], p.width, p.height, p.channels, bytes.data(), p.width * p.channels)) {
            std::fprintf(stderr, "pnm_to_png: cannot write %s\n", argv[2]);
            return 1;
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "pnm_to_png: %s\n", e.what());
        return 1;
    }
    return 0;
}
