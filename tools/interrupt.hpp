// SPDX-License-Identifier: MIT
#pragma once

namespace sonarsynth::cli {

/// Makes SIGINT, SIGTERM and SIGHUP remove this process's uncommitted temporary outputs
/// (remove_pending_temporaries) and then end the process with exit code 128 + signal number.
///
/// Call it first in main, before any thread starts: it blocks those signals in the calling
/// thread, so that every thread started later inherits the mask, and starts one thread that
/// waits for them with sigwait(). The cleanup thus runs as ordinary code, not in a signal handler,
/// and takes the same lock as commits, so it never interrupts a directory swap half-way.
void install_interrupt_cleanup();

}  // namespace sonarsynth::cli
