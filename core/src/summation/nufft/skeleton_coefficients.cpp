// Points' coefficients on skeleton nodes (skeleton_coefficients.h).
#include "summation/nufft/skeleton_coefficients.h"

#include "base/parallel.h"


namespace wavecam::detail {
namespace {

using cdouble = std::complex<double>;

// The skeleton's coefficients split into real and imaginary, padded to kNodeBatch: one vector of
// eight per node, written so with GCC's vector extension.
typedef float Eight __attribute__((vector_size(32)));
static_assert(kNodeBatch * sizeof(float) == sizeof(Eight));

// One point's coefficients on up to kNodeBatch skeleton nodes: sum_k L[k] (tr + i ti)[k][q].
__attribute__((target_clones("arch=x86-64-v3", "default")))
void node_sums(const float* L, int nodes, const Eight* tr, const Eight* ti, Eight& out_re, Eight& out_im) {
    Eight ar = {}, ai = {};
    for (int k = 0; k < nodes; ++k) {
        ar += L[k] * tr[k];
        ai += L[k] * ti[k];
    }
    out_re = ar;
    out_im = ai;
}

}  // namespace

void skeleton_coefficients(const BoxPointWeights& points, const SkeletonBatch& skeleton_batch, const cdouble* factor,
                           std::vector<cfloat>& out, int nthreads) {
    const AxisWeights& aw = points.axis;
    const int dims = points.dims, nodes = points.nodes;
    const size_t count = points.count;
    const NodeSkeleton& sk = skeleton_batch.skeleton;
    const int j0 = skeleton_batch.j0, batch = skeleton_batch.batch;
    const int r = sk.rank();
    std::vector<Eight> re(nodes), im(nodes);
    for (int k = 0; k < nodes; ++k)
        for (int q = 0; q < kNodeBatch; ++q) {
            const cdouble t = q < batch ? sk.coeff[size_t(k) * r + j0 + q] : 0.0;
            re[k][q] = float(t.real());
            im[k][q] = float(t.imag());
        }
    out.resize(count * batch);
    const int n0 = aw.n[0], n1 = dims > 1 ? aw.n[1] : 1, n2 = dims > 2 ? aw.n[2] : 1;
    parallel_team(thread_count(nthreads), [&](Team& team) {
        std::vector<float> L(nodes);
        Eight sr, si;
        team.for_blocks(0, int64_t(count), [&](int64_t i) {
            const float* w = aw.w.data() + size_t(i) * aw.stride;
            int q = 0;
            for (int c = 0; c < n2; ++c)
                for (int b = 0; b < n1; ++b) {
                    const float lbc = (dims > 1 ? w[aw.offset[1] + b] : 1.0f) * (dims > 2 ? w[aw.offset[2] + c] : 1.0f);
                    for (int a = 0; a < n0; ++a) L[q++] = lbc * w[aw.offset[0] + a];
                }
            node_sums(L.data(), nodes, re.data(), im.data(), sr, si);
            cfloat* o = out.data() + size_t(i) * batch;
            if (factor)
                for (int j = 0; j < batch; ++j) o[j] = cfloat(factor[i] * cdouble(sr[j], si[j]));
            else
                for (int j = 0; j < batch; ++j) o[j] = cfloat(sr[j], si[j]);
        });
    });
}

}  // namespace wavecam::detail
