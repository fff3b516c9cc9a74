// What the Vulkan tests share: a skip where the build has no Vulkan evaluator, a handle on the
// device the environment gives (ctest: lavapipe), and the relative RMS they are bounded by.
#pragma once
#include <gtest/gtest.h>

#include <cmath>
#include <complex>

#include "wavecam/compute_device.h"

// Skips where the build has no Vulkan evaluator; never passes silently otherwise.
#ifdef WAVECAM_HAVE_VULKAN
#define REQUIRE_VULKAN()
#else
#define REQUIRE_VULKAN() GTEST_SKIP() << "built without the Vulkan evaluator"
#endif

namespace wavecam::test {

// A handle on the Vulkan device the environment gives.
inline ComputeDevice gpu_device() {
    ComputeDevice d = ComputeDevice::create(Device::Gpu);
    EXPECT_TRUE(d.gpu()) << d.error();
    return d;
}

// sqrt(sum |got - want|^2 / sum |want|^2).
template <class A, class B>
double relative_rms(const A& got, const B& want) {
    double e = 0, n = 0;
    for (size_t i = 0; i < want.size(); ++i) {
        e += std::norm(std::complex<double>(got[i]) - std::complex<double>(want[i]));
        n += std::norm(std::complex<double>(want[i]));
    }
    return std::sqrt(e / n);
}

}  // namespace wavecam::test
