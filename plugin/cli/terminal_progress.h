// Progress people can read: the estimate before the work, then on a terminal a bar with the
// time left, and in a log (stderr not a terminal, as under Slurm) a line every 10 s or 5%.
#pragma once
#include <string>

#include "wavecam/aperture.h"
#include "wavecam/diffract_image.h"
#include "wavecam/progress.h"

namespace wavecam::cli {

// Prints "LABEL: " and the job's estimate line (front/estimate_line.h) on stderr.
void print_estimate(const std::string& label, const JobEstimate& estimate);

// What an aperture multiplies the work by, for the estimate printed before it: "aperture
// sieve:2000 (245001 holes): about 3.1e+09 pinhole samples per PSF" (zone plates: their zones).
std::string aperture_work(const Aperture& aperture, double samples);

// Returns a ProgressFn that draws "label [#####....] 42%  2m10s left" on a terminal, or writes
// "label: 42% after 1m35s, about 2m10s left" lines to a log; it returns false (stop) once
// a terminating signal has been received.
ProgressFn terminal_progress(const std::string& label);
// Ends the bar's line (if one was drawn).
void finish_progress();
// Installs handlers for every catchable terminating signal (INT, TERM, HUP, PIPE, XCPU, XFSZ,
// USR1, USR2) that ask running work to stop; work that has not stopped 1.5 s later (or a second
// signal) ends the process at once, exit 128 + N, removing the temporary being written
// (atomic_write.h).
void install_interrupt_handlers();
bool interrupted();
// What the watchdog prints when it ends the process ("wavecam apply: in.exr: interrupted").
void set_interrupt_message(const std::string& message);
// The exit status for the signal received: 128 + N (130 for SIGINT, 143 for SIGTERM).
int interrupted_status();

}  // namespace wavecam::cli
