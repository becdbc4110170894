// LDR-FLIP's feature pipeline (HPG 2020 §4.3): edges (first derivative of a Gaussian) and points
// (second derivative) on the achromatic channel, whose differences between the two images make
// the colour error count more: a lost edge or a new speck is seen even where colours are close.
#include <cmath>
#include <numbers>

#include "flip_filter.h"
#include "pnb_reference/flip.h"

namespace pnb::reference::flip_detail {

namespace {

// The 1D factors of the separable detectors. The paper's 2D kernel for x is d(x) g(y): g a
// Gaussian of standard deviation sigma = w/2 degrees (w the detector's peak-to-trough width), d its
// first or second derivative; the positive weights sum to 1 and the negative ones to -1. As g > 0,
// that normalisation is d's positive and negative parts scaled apart, times g over its sum.
struct FeatureKernels {
    std::vector<float> smooth, edge, point;
};

std::vector<float> normalizeSigned(std::vector<double> taps) {
    double positive = 0.0, negative = 0.0;
    for (double t : taps)
        (t > 0 ? positive : negative) += t;
    std::vector<float> out(taps.size());
    for (size_t i = 0; i < taps.size(); ++i)
        out[i] = float(taps[i] > 0 ? taps[i] / positive : taps[i] < 0 ? taps[i] / -negative : 0.0);
    return out;
}

FeatureKernels featureKernels(double ppd) {
    const double sigma = 0.5 * flip_constants::kFeatureWidthDegrees * ppd; // pixels
    const int r = int(std::ceil(3.0 * sigma));
    std::vector<double> g, edge, point;
    double gSum = 0.0;
    for (int k = -r; k <= r; ++k) {
        const double gauss = std::exp(-double(k) * k / (2.0 * sigma * sigma));
        g.push_back(gauss);
        gSum += gauss;
        edge.push_back(-k * gauss);
        point.push_back((double(k) * k / (sigma * sigma) - 1.0) * gauss);
    }
    FeatureKernels kernels;
    for (double v : g)
        kernels.smooth.push_back(float(v / gSum));
    kernels.edge = normalizeSigned(edge);
    kernels.point = normalizeSigned(point);
    return kernels;
}

// |(response along x, response along y)| of one detector.
std::vector<float> detectorMagnitude(const Plane& y, const std::vector<float>& derivative,
                                     const std::vector<float>& smooth) {
    const Plane alongX = correlateSeparable(y, derivative, smooth);
    const Plane alongY = correlateSeparable(y, smooth, derivative);
    std::vector<float> magnitude(y.v.size());
    for (size_t p = 0; p < magnitude.size(); ++p)
        magnitude[p] = std::hypot(alongX.v[p], alongY.v[p]);
    return magnitude;
}

} // namespace

std::vector<float> featureError(const Plane& testY, const Plane& referenceY, double ppd) {
    const FeatureKernels k = featureKernels(ppd);
    const std::vector<float> edgeT = detectorMagnitude(testY, k.edge, k.smooth);
    const std::vector<float> edgeR = detectorMagnitude(referenceY, k.edge, k.smooth);
    const std::vector<float> pointT = detectorMagnitude(testY, k.point, k.smooth);
    const std::vector<float> pointR = detectorMagnitude(referenceY, k.point, k.smooth);
    std::vector<float> error(edgeT.size());
    for (size_t p = 0; p < error.size(); ++p) {
        const double difference = std::max(std::abs(double(edgeT[p]) - edgeR[p]),
                                           std::abs(double(pointT[p]) - pointR[p]));
        // Each response is at most sqrt(2) (unit positive and negative weights on Y in [0, 1]).
        error[p] =
            float(std::pow(difference / std::numbers::sqrt2, flip_constants::kFeatureExponent));
    }
    return error;
}

} // namespace pnb::reference::flip_detail
