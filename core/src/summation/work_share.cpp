#include "wavecam/work_share.h"

#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace wavecam {

Result<WorkShare> work_share(int index, int count, int wavelengths, int runs, int height) {
    auto fail = [](const std::string& m) { return Result<WorkShare>::failure("share: " + m); };
    if (count < 1 || index < 1 || index > count) {
        std::ostringstream m;
        m << "expected share K of N with 1 <= K <= N, got " << index << "/" << count;
        return fail(m.str());
    }
    const long units = long(wavelengths) * runs;
    if (units < 1 || height < 1) return fail("the job has no work to share");
    if (count > units * height) {
        std::ostringstream m;
        m << count << " shares are more than the job's " << units << " units x " << height
          << " film rows; use at most " << units * height;
        return fail(m.str());
    }
    WorkShare s;
    s.index = index;
    s.count = count;
    const long k = index - 1;
    if (count <= units) {
        // Contiguous, near-equal ranges of units; the whole film.
        s.unit_begin = int(k * units / count);
        s.unit_end = int((k + 1) * units / count);
        s.row_begin = 0;
        s.row_end = height;
        return Result<WorkShare>::success(s);
    }
    // More shares than units: unit u takes shares [u N / U, (u + 1) N / U), each a band of rows.
    const long u = k * units / count;  // the unit whose share range holds k
    const long first = (u * count + units - 1) / units, last = ((u + 1) * count + units - 1) / units;
    const long bands = last - first, b = k - first;
    s.unit_begin = int(u);
    s.unit_end = int(u + 1);
    s.row_begin = int(b * height / bands);
    s.row_end = int((b + 1) * height / bands);
    return Result<WorkShare>::success(s);
}

Result<WorkShare> parse_share(const std::string& text) {
    int k = 0, n = 0, used = 0;
    if (std::sscanf(text.c_str(), "%d/%d%n", &k, &n, &used) != 2 || used != int(text.size()) || n < 1 || k < 1 ||
        k > n)
        return Result<WorkShare>::failure("--share: expected K/N with 1 <= K <= N, e.g. 3/8, got '" + text + "'");
    WorkShare s;
    s.index = k;
    s.count = n;
    return Result<WorkShare>::success(s);
}

std::string describe_share(const WorkShare& s, int runs) {
    std::ostringstream d;
    const int w0 = s.unit_begin / runs, w1 = (s.unit_end - 1) / runs;
    if (s.unit_end - s.unit_begin == 1)
        d << "wavelength " << w0 << " run " << s.unit_begin % runs;
    else
        d << "units " << s.unit_begin << "-" << s.unit_end - 1 << " (wavelength " << w0 << " run "
          << s.unit_begin % runs << " to wavelength " << w1 << " run " << (s.unit_end - 1) % runs << ")";
    d << ", rows " << s.row_begin << "-" << s.row_end - 1;
    return d.str();
}

}  // namespace wavecam
