// The pixel-by-pixel mean of images of one size, written as a PFM (linear floats): a reference made
// of independent renders (bench/peers/float_race.sh averages two halves, whose difference is the
// reference's own noise).
//
//   image_mean OUT.pfm IN1 IN2 [IN...]     (IN: PNG, EXR or PFM)
//
// Exit status: 0 on success, 2 on a usage error, unreadable inputs or mismatched sizes, 1 when the
// output cannot be written.
#include "core/io/image_io.h"

#include <cstdio>
#include <exception>
#include <string>

using caustica::Image;

int main(int argc, char** argv) {
    if (argc < 4) {
        std::fprintf(stderr, "usage: image_mean OUT.pfm IN1 IN2 [IN...]\n");
        return 2;
    }
    const std::string out = argv[1];
    if (out.size() < 4 || out.compare(out.size() - 4, 4, ".pfm") != 0) {
        std::fprintf(stderr, "image_mean: the output is a PFM (OUT.pfm), got %s\n", out.c_str());
        return 2;
    }
    Image sum;
    const int count = argc - 2;
    try {
        for (int i = 2; i < argc; ++i) {
            const Image image = caustica::read_image_file(argv[i]);
            if (i == 2) {
                sum = image;
                continue;
            }
            if (image.width != sum.width || image.height != sum.height) {
                std::fprintf(stderr, "image_mean: %s differs in size from %s\n", argv[i], argv[2]);
                return 2;
            }
            for (std::size_t p = 0; p < sum.pixels.size(); ++p) sum.pixels[p] += image.pixels[p];
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "image_mean: %s\n", e.what());
        return 2;
    }
    for (glm::vec3& p : sum.pixels) p /= static_cast<float>(count);
    try {
        caustica::write_pfm_atomic(out, sum);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "image_mean: %s\n", e.what());
        return 1;
    }
    return 0;
}
