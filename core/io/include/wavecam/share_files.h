// Part files: one share (work_share.h) of a scene-sum job as an EXR, and their merge.
// A part holds, per unit (wavelength w, run r) of its share and per sign of the spectral power,
// the film irradiance that run adds before the colour step (one float channel
// "w003.r001.pos"/".neg", rows of its band only), and in its header what was summed, the job's
// settings as given, a fingerprint of the input file's bytes and a checksum of its pixels.
// Merging replays the stored units through the single-machine colour step in the
// single-machine order, so the merged image equals the single-machine one bit for bit (on the
// same build and CPU type; see docs/farm.md).
#pragma once
#include <OpenImageIO/imagebuf.h>
#include <map>
#include <string>
#include <vector>
#include "wavecam/diffract_image.h"
#include "wavecam/work_share.h"

namespace wavecam {

using SettingsText = std::map<std::string, std::string>;  // key -> value as given, e.g. pinhole -> 0.2mm

// FNV-1a 64 of the file's bytes, as 16 hex digits; errors name the file.
Result<std::string> file_fingerprint(const std::string& path);

// The fingerprint of a whole job: the input's fingerprint and every setting, 16 hex digits.
std::string job_fingerprint(const std::string& input_fingerprint, const SettingsText& settings);

// What a part records of its job for the merge: the input file's path and the settings as given.
struct JobRecord {
    const std::string& input_path;
    const SettingsText& settings;
};

// Computes share share.index/share.count (as parse_share gives it; the units and rows are
// resolved here) of the scene-sum job `diffract(src, opt)` describes into `part` (failures as
// DiffractPlan::diffract's). `job` is recorded for the merge; opt.on_estimate hears the share's
// own terms, opt.max_terms bounds them.
Result<bool> diffract_share(OIIO::ImageBuf& part, const OIIO::ImageBuf& src, const DiffractOptions& opt,
                            const JobRecord& job, const WorkShare& share, int nthreads = 0);

struct PartFile {
    std::string path;
    WorkShare share;
    int wavelengths = 0, runs = 0, width = 0, height = 0;
    std::string input, input_fingerprint, job;
    SettingsText settings;
    OIIO::ImageBuf image;
};

// Reads one part file and checks it: readable, a wavecam part, its pixels match the checksum.
// Errors read "PATH: cannot be read as an image (...)", "PATH: corrupt: ..." or
// "PATH: not a wavecam part file: ...".
Result<PartFile> read_part(const std::string& path);

// Whether `parts` make exactly one whole job: every share 1..N once, all of one input, seed
// and settings. The error has one line per problem, each naming the share and its file.
Result<bool> check_part_set(const std::vector<PartFile>& parts);

// The propagator that gives back the stored units (for opt.scene_sum_propagator in the merge).
MonochromePropagator stored_units(const std::vector<PartFile>& parts);

}  // namespace wavecam
