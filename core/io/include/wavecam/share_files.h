// Share files: one share (work_share.h) of a scene-sum job as an EXR, and their merge.
// A share file holds, per unit (wavelength w, run r) of its share and per sign of the spectral
// power, the film irradiance that run adds before the colour step (one float channel
// "w003.r001.pos"/".neg", rows of its band only), and in its header (wavecam.share,
// wavecam.share.*) what was summed, the job's settings as given, a fingerprint of the input
// file's bytes and a checksum of its pixels.
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

// What a share file records of its job for the merge: the input file's path and the settings as given.
struct JobRecord {
    const std::string& input_path;
    const SettingsText& settings;
};

// Computes share share.index/share.count (as parse_share gives it; the units and rows are
// resolved here) of the scene-sum job `diffract(src, opt)` describes into `share_image` (failures as
// DiffractPlan::diffract's). `job` is recorded for the merge; opt.on_estimate hears the share's
// own terms, opt.max_terms bounds them.
Result<bool> diffract_share(OIIO::ImageBuf& share_image, const OIIO::ImageBuf& src, const DiffractOptions& opt,
                            const JobRecord& job, const WorkShare& share, int nthreads = 0);

struct ShareFile {
    std::string path;
    WorkShare share;
    int wavelengths = 0, runs = 0, width = 0, height = 0;
    std::string input, input_fingerprint, job;
    std::string decision;  // the job's decision as this share made it (decision_text); "" in older files
    SettingsText settings;
    OIIO::ImageBuf image;
    bool old_spelling = false;  // its header spells the records wavecam.part.* (kOldShareRecordNote)
};

// A share record of a share file's header, by its name: "" for wavecam.share (the share, "K/N"),
// else the name after "wavecam.share." ("job", "summed", "setting.seed", ...). The spelling
// wavecam.part.share / wavecam.part.NAME is read too, and then sets *old_spelling (when given);
// "" when the header has neither.
std::string share_record(const OIIO::ImageSpec& spec, const std::string& name, bool* old_spelling = nullptr);

// The one-line note a front shows once when a share file's header spells its records wavecam.part.*.
inline constexpr const char* kOldShareRecordNote = "wavecam.part.* in a share file's header is now spelt "
                                                   "wavecam.share.* (same meaning)";

// Reads one share file and checks it: readable, a wavecam share, its pixels match the checksum.
// Errors read "PATH: cannot be read as an image (...)", "PATH: corrupt: ..." or
// "PATH: not a wavecam share file: ...".
Result<ShareFile> read_share(const std::string& path);

// Whether `shares` make exactly one whole job: every share 1..N once, all of one input, seed
// and settings. The error has one line per problem, each naming the share and its file.
Result<bool> check_share_set(const std::vector<ShareFile>& shares);

// The propagator that gives back the stored units (for opt.scene_sum_propagator in the merge).
MonochromePropagator stored_units(const std::vector<ShareFile>& shares);

}  // namespace wavecam
