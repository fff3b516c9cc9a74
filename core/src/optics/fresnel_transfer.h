// Many zones: the field PSF by Fresnel propagation of the pupil with an FFT transfer function
// on a grid at a fraction of a film pixel (fresnel_transfer.cpp). Internal to core.
#pragma once
#include <cmath>
#include <vector>

#include "optics/fresnel_field.h"

namespace wavecam::detail {

struct TransferPlan {
    int sub = 0;             // grid points per kernel pixel side
    int n = 0;               // grid size (FFT length), at least
    double h = 0;            // pitch on the pupil plane (m)
    bool symmetric = false;  // the field is point-symmetric: half the inverse transform
    bool mirror_even = false;  // and the pupil even in x and in y: its spectrum by packed real lines
    // the inverse transform and the transfer function (the pupil's forward transform is
    // shared by a table's requests at one depth, see PupilSpectrum)
    double cost() const {
        return (symmetric ? 0.5 : 1.0) * (5.0 * double(n) * n * std::log2(double(n)) + 8.0 * double(n) * n);
    }
};

TransferPlan plan_transfer(const FieldPsfRequest& q, const FieldGeometry& g);

// The kernel's (2 radius + 1)^2 weights by the plan.
std::vector<float> kernel_by_transfer(const FieldPsfRequest& q, const FieldGeometry& g, const TransferPlan& plan);

// The pupil spectra each thread keeps (see PupilSpectrum in fresnel_transfer.cpp).
constexpr int kSpectraKept = 4;

}  // namespace wavecam::detail
