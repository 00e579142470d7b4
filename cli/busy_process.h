#pragma once
// vfsd bench --busy and vfsd bench --latency --busy: another program at work
// beside the bench, as a desktop user's other work would be.

#include <sys/wait.h>
#include <unistd.h>
#include <csignal>

#include "base/error.h"

namespace vfsd::cli {

// A child process that keeps one core busy until this goes out of scope.
class BusyProcess {
public:
    BusyProcess() : pid_(fork()) {
        if (pid_ < 0) throw IoError("bench --busy: could not start the busy process");
        if (pid_ == 0)
            for (volatile unsigned long spin = 0;; spin = spin + 1) {
            }
    }
    ~BusyProcess() {
        kill(pid_, SIGKILL);
        waitpid(pid_, nullptr, 0);
    }
    BusyProcess(const BusyProcess&) = delete;
    BusyProcess& operator=(const BusyProcess&) = delete;

private:
    pid_t pid_;
};

}  // namespace vfsd::cli
