#include "py_interrupt.h"

#include <pybind11/pybind11.h>

#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>

#include "imagefile/safe_output.h"

namespace py = pybind11;

namespace spectralize::python {

bool run_interruptibly(const std::function<void(const StopFlag& stop)>& work) {
  StopFlag stop{false};
  std::mutex mutex;
  std::condition_variable finished;
  bool done = false;
  std::exception_ptr failure;
  bool interrupted = false;
  {
    py::gil_scoped_release release;
    std::thread worker([&] {
      ensure_signal_stack();  // a crash in the work still removes its temporaries
      try {
        work(stop);
      } catch (...) {
        failure = std::current_exception();
      }
      std::lock_guard<std::mutex> lock(mutex);
      done = true;
      finished.notify_all();
    });
    std::unique_lock<std::mutex> lock(mutex);
    while (!done) {
      if (finished.wait_for(lock, std::chrono::milliseconds(50), [&] { return done; })) break;
      if (interrupted) continue;  // already asked to stop: wait for the work to return
      lock.unlock();
      {
        py::gil_scoped_acquire acquire;
        // Runs Python's handlers on this (the main) thread; KeyboardInterrupt stays set.
        interrupted = PyErr_CheckSignals() != 0;
      }
      if (interrupted) stop = true;
      lock.lock();
    }
    lock.unlock();
    worker.join();
  }
  if (failure && !interrupted) std::rethrow_exception(failure);
  return !interrupted;
}

}  // namespace spectralize::python
