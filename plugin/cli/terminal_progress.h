// A progress bar on stderr when it is a terminal, nothing otherwise.
#pragma once
#include <string>
#include "wavecam/progress.h"

namespace wavecam::cli {

// Returns a ProgressFn that draws "label [#####....] 42%" on a terminal and is silent
// otherwise; it returns false (stop) once SIGINT/SIGTERM has been received.
ProgressFn terminal_progress(const std::string& label);
// Ends the bar's line (if one was drawn).
void finish_progress();
// Installs SIGINT/SIGTERM handlers that ask running work to stop.
void install_interrupt_handlers();
bool interrupted();

}  // namespace wavecam::cli
