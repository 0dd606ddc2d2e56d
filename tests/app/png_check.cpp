// png_check FILE [--min-cloth FRACTION] [--min-grey FRACTION] [--hue LO HI MIN_FRACTION MAX_FRACTION]...
//           [--differs OTHER MIN_FRACTION] [--matches OTHER MAX_FRACTION]
// Fails unless a viewer screenshot shows something: at least FRACTION of its pixels in the cloth's
// colour families (warm orange front, blue back) and, if asked, in the colliders' greys. The dark
// background gradient falls in neither family. --hue counts saturated, bright pixels with a hue
// in [LO, HI] degrees (LO > HI wraps through 0), e.g. the overlay's boxes or contact points;
// --differs asks that at least MIN_FRACTION of the pixels differ visibly from those of OTHER,
// --matches that at most MAX_FRACTION do.
#include <stb_image.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {

struct Hsv {
  double hue;         // degrees in [0, 360)
  double saturation;  // [0, 1]
  double value;       // [0, 1]
};

Hsv to_hsv(const unsigned char* rgb) {
  const double r = rgb[0] / 255.0, g = rgb[1] / 255.0, b = rgb[2] / 255.0;
  const double max = std::max({r, g, b}), min = std::min({r, g, b});
  const double chroma = max - min;
  double hue = 0.0;
  if (chroma > 0.0) {
    if (max == r) {
      hue = 60.0 * std::fmod((g - b) / chroma + 6.0, 6.0);
    } else if (max == g) {
      hue = 60.0 * ((b - r) / chroma + 2.0);
    } else {
      hue = 60.0 * ((r - g) / chroma + 4.0);
    }
  }
  return {hue, max > 0.0 ? chroma / max : 0.0, max};
}

bool is_cloth(const Hsv& c) {
  const bool warm = c.hue >= 10.0 && c.hue <= 50.0 && c.saturation >= 0.45 && c.value >= 0.25;
  const bool blue = c.hue >= 200.0 && c.hue <= 240.0 && c.saturation >= 0.45 && c.value >= 0.2;
  return warm || blue;
}

bool is_grey(const Hsv& c) { return c.saturation <= 0.08 && c.value >= 0.25; }

bool in_hue(const Hsv& c, double low, double high) {
  if (c.saturation < 0.4 || c.value < 0.4) return false;
  return low <= high ? (c.hue >= low && c.hue <= high) : (c.hue >= low || c.hue <= high);
}

struct HueCheck {
  double low, high, min_fraction, max_fraction;
};

int usage() {
  std::fprintf(stderr,
               "usage: png_check FILE [--min-cloth FRACTION] [--min-grey FRACTION] "
               "[--hue LO HI MIN_FRACTION MAX_FRACTION]... [--differs OTHER MIN_FRACTION] "
               "[--matches OTHER MAX_FRACTION]\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return usage();
  const std::string path = argv[1];
  double min_cloth = 0.01;
  double min_grey = 0.0;
  std::vector<HueCheck> hue_checks;
  std::string other_path;
  double min_differing = 0.0;
  bool matches = false;  // --matches: at most max_differing differ
  double max_differing = 1.0;
  for (int k = 2; k < argc; ++k) {
    if (k + 1 >= argc) return usage();
    if (std::strcmp(argv[k], "--min-cloth") == 0) {
      min_cloth = std::atof(argv[++k]);
    } else if (std::strcmp(argv[k], "--min-grey") == 0) {
      min_grey = std::atof(argv[++k]);
    } else if (std::strcmp(argv[k], "--hue") == 0 && k + 4 < argc) {
      hue_checks.push_back({std::atof(argv[k + 1]), std::atof(argv[k + 2]), std::atof(argv[k + 3]), std::atof(argv[k + 4])});
      k += 4;
    } else if (std::strcmp(argv[k], "--differs") == 0 && k + 2 < argc) {
      other_path = argv[k + 1];
      min_differing = std::atof(argv[k + 2]);
      k += 2;
    } else if (std::strcmp(argv[k], "--matches") == 0 && k + 2 < argc) {
      other_path = argv[k + 1];
      matches = true;
      max_differing = std::atof(argv[k + 2]);
      k += 2;
    } else {
      return usage();
    }
  }

  int width = 0, height = 0, channels = 0;
  unsigned char* pixels = stbi_load(path.c_str(), &width, &height, &channels, 3);
  if (pixels == nullptr) {
    std::fprintf(stderr, "png_check: %s: cannot read PNG: %s\n", path.c_str(), stbi_failure_reason());
    return 1;
  }
  long cloth = 0, grey = 0;
  std::vector<long> hue_counts(hue_checks.size(), 0);
  const long total = static_cast<long>(width) * height;
  for (long i = 0; i < total; ++i) {
    const Hsv colour = to_hsv(pixels + 3 * i);
    if (is_cloth(colour)) ++cloth;
    if (is_grey(colour)) ++grey;
    for (size_t h = 0; h < hue_checks.size(); ++h) hue_counts[h] += in_hue(colour, hue_checks[h].low, hue_checks[h].high);
  }

  bool ok = true;
  for (size_t h = 0; h < hue_checks.size(); ++h) {
    const HueCheck& check = hue_checks[h];
    const double fraction = static_cast<double>(hue_counts[h]) / std::max(total, 1L);
    const bool passed = fraction >= check.min_fraction && fraction <= check.max_fraction;
    std::printf("%s: hue %g..%g %.3f%% (need %.3f%% to %.3f%%)%s\n", path.c_str(), check.low, check.high,
                100.0 * fraction, 100.0 * check.min_fraction, 100.0 * check.max_fraction, passed ? "" : " FAILED");
    ok = ok && passed;
  }
  if (!other_path.empty()) {
    int other_width = 0, other_height = 0, other_channels = 0;
    unsigned char* other = stbi_load(other_path.c_str(), &other_width, &other_height, &other_channels, 3);
    if (other == nullptr || other_width != width || other_height != height) {
      std::fprintf(stderr, "png_check: %s: cannot read it, or its size differs\n", other_path.c_str());
      ok = false;
    } else {
      long differing = 0;
      for (long i = 0; i < 3 * total; i += 3) {
        const int change = std::abs(pixels[i] - other[i]) + std::abs(pixels[i + 1] - other[i + 1]) +
                           std::abs(pixels[i + 2] - other[i + 2]);
        differing += change > 24;
      }
      const double fraction = static_cast<double>(differing) / std::max(total, 1L);
      const bool passed = matches ? fraction <= max_differing : fraction >= min_differing;
      std::printf("%s: %.3f%% of pixels differ from %s (need %s %.3f%%)%s\n", path.c_str(), 100.0 * fraction,
                  other_path.c_str(), matches ? "at most" : "at least",
                  100.0 * (matches ? max_differing : min_differing), passed ? "" : " FAILED");
      ok = ok && passed;
    }
    stbi_image_free(other);
  }
  stbi_image_free(pixels);

  const double cloth_fraction = static_cast<double>(cloth) / std::max(total, 1L);
  const double grey_fraction = static_cast<double>(grey) / std::max(total, 1L);
  std::printf("%s: %dx%d, cloth %.2f%% (need %.2f%%), grey %.2f%% (need %.2f%%)\n", path.c_str(), width,
              height, 100.0 * cloth_fraction, 100.0 * min_cloth, 100.0 * grey_fraction, 100.0 * min_grey);
  ok = ok && total > 0 && cloth_fraction >= min_cloth && grey_fraction >= min_grey;
  if (!ok)
    std::fprintf(stderr, "png_check: %s does not show the expected cloth and colliders\n", path.c_str());
  return ok ? 0 : 1;
}
