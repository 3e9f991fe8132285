// How the error estimate's blur probe reads model caustics (docs/ACCURACY.md, "A third disc").
//
//     build/probe_model
//
// A caustic that varies across an edge only (x, in pixels) is seen through discs of radius rho:
// its disc average at x is the mean of E(x + rho s) over the disc, s distributed as a chord across
// a unit disc, (2 / pi) sqrt(1 - s^2). Each pixel shows the mean of the disc averages over its
// width (the jittered samples of the passes), and its true value is the mean of E over the same
// width. For each caustic and radius r it prints, summed over the pixels around the edge:
//   true/P      the RMS blur (pixel value at r less the true value) over the RMS of the two-disc
//               probe P = 2 (L_r - L_{r/sqrt 2}), which the renderer takes for the blur (1: right);
//   Q/P         sum Q^2 / sum P^2 for a third disc's probe Q = 2 (L_{r/sqrt 2} - L_{r/2}) (1/4
//               for a smooth caustic, whose blur grows as r^2);
//   PQ/P        sum P Q / sum P^2 (products change sign where the disc is about a pixel wide);
//   3disc/true  the blur read by -0.26 sum P^2 + 5.05 sum Q^2, over the true blur.
// No photons and no noise: what the probes would read with infinitely many.
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace {

using Caustic = std::function<double(double)>;

constexpr int chords = 400, subpixels = 16;

/// Midpoints of [-1, 1] and their chord weights, normalised to sum to 1 (a constant caustic has
/// no blur).
struct Chords {
    std::vector<double> s, w;
    Chords() {
        double total = 0.0;
        for (int i = 0; i < chords; ++i) {
            s.push_back(-1.0 + (2.0 * i + 1.0) / chords);
            w.push_back(std::sqrt(1.0 - s.back() * s.back()));
            total += w.back();
        }
        for (double& x : w) x /= total;
    }
};

double disc_average(const Chords& c, const Caustic& f, double x, double rho) {
    double sum = 0.0;
    for (int i = 0; i < chords; ++i) sum += c.w[i] * f(x + rho * c.s[i]);
    return sum;
}

double pixel_mean(const Caustic& g, double x0) {
    double sum = 0.0;
    for (int k = 0; k < subpixels; ++k) sum += g(x0 + (k + 0.5) / subpixels);
    return sum / subpixels;
}

struct Reading {
    double true_over_p, q_over_p, pq_over_p, three_over_true;
};

Reading measure(const Chords& c, const Caustic& f, double r) {
    double blur2 = 0.0, pp = 0.0, qq = 0.0, pq = 0.0;
    const int span = static_cast<int>(4.0 * r) + 4;
    for (int x0 = -span; x0 < span; ++x0) {
        const double truth = pixel_mean(f, x0);
        const double l1 = pixel_mean([&](double x) { return disc_average(c, f, x, r); }, x0);
        const double l2 = pixel_mean([&](double x) { return disc_average(c, f, x, r / std::sqrt(2.0)); }, x0);
        const double l3 = pixel_mean([&](double x) { return disc_average(c, f, x, r / 2.0); }, x0);
        const double p = 2.0 * (l1 - l2), q = 2.0 * (l2 - l3);
        blur2 += (l1 - truth) * (l1 - truth);
        pp += p * p;
        qq += q * q;
        pq += p * q;
    }
    if (pp <= 1e-12 * blur2) {  // a line thinner than the sampling sees: the probe reads nothing
        const double nan = std::numeric_limits<double>::quiet_NaN();
        return {std::numeric_limits<double>::infinity(), nan, nan, 0.0};
    }
    const double three = std::fmax(0.0, -0.26 * pp + 5.05 * qq);
    return {std::sqrt(blur2 / pp), qq / pp, pq / pp, std::sqrt(three / blur2)};
}

}  // namespace

int main() {
    const Chords c;
    for (double r : {3.0, 1.5, 1.0, 0.75}) {
        auto gauss = [](double sigma) -> Caustic { return [sigma](double x) { return std::exp(-x * x / (2 * sigma * sigma)); }; };
        const std::vector<std::pair<std::string, Caustic>> caustics = {
            {"smooth (quadratic)", [](double x) { return 1.0 + 0.01 * x * x; }},
            {"Gaussian, sigma 2 r", gauss(2.0 * r)},
            {"Gaussian, sigma r", gauss(r)},
            {"Gaussian, sigma r/2", gauss(0.5 * r)},
            {"Gaussian, sigma r/4", gauss(0.25 * r)},
            {"straight step", [](double x) { return x < 0.0 ? 1.0 : 0.0; }},
            {"line r/4 wide", [r](double x) { return std::fabs(x) < r / 8.0 ? 1.0 : 0.0; }},
            {"fold, 1/sqrt(x) (at most 20)", [](double x) { return x > 0.0 ? std::fmin(1.0 / std::sqrt(x), 20.0) : 0.0; }},
        };
        std::printf("r = %g pixels\n  %-30s %7s %6s %6s %10s\n", r, "caustic", "true/P", "Q/P", "PQ/P", "3disc/true");
        for (const auto& [name, f] : caustics) {
            const Reading m = measure(c, f, r);
            std::printf("  %-30s %7.2f %6.3f %6.2f %10.2f\n", name.c_str(), m.true_over_p, m.q_over_p, m.pq_over_p,
                        m.three_over_true);
        }
    }
    return 0;
}
