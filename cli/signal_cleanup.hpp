#pragma once
/// @file signal_cleanup.hpp
/// SIGINT, SIGTERM, SIGHUP and SIGXFSZ remove the temporary file of a save in progress
/// (granular::remove_pending_temporaries) before the signal takes its default action, so an
/// interrupted `granular export` leaves no "<out>.tmp-<pid>" behind.

namespace granular::cli {

/// Installs the handler for those signals, except any this process was started ignoring (nohup).
void install_signal_cleanup();

}  // namespace granular::cli
