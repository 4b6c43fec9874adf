#pragma once
// Ctrl-C during long calls (docs/DESIGN.md §13): the work runs on its own thread while the
// calling thread, which Python delivers signals to, checks for them every 50 ms; an interrupt
// asks the work to stop, waits for it, and leaves KeyboardInterrupt pending for the caller.

#include <atomic>
#include <functional>

namespace spectralize::python {

/// The flag a piece of work polls: set once Ctrl-C (or another signal whose Python handler
/// raises) has been seen.
using StopFlag = std::atomic<bool>;

/// Runs `work(stop)` on a new thread, with the GIL released, while this thread checks for
/// signals (PyErr_CheckSignals) every 50 ms. Returns true when the work ran to its end
/// (rethrowing what it threw); false when a signal handler raised: `stop` was set, the work
/// has returned (it must stop within a fraction of a second of `stop`), and the Python error
/// (KeyboardInterrupt) is set for the caller to report and raise. Needs the GIL. Cost: a
/// thread, and the work.
bool run_interruptibly(const std::function<void(const StopFlag& stop)>& work);

}  // namespace spectralize::python
