// child_process.h — runs a tool as a child process and reports what it cost: exit code, output,
// wall time and peak resident memory (wait4's ru_maxrss), optionally under an address-space
// limit. Header-only, for tests that check a CLI fails fast and small.
#pragma once

#include "sanitizers.h"

#include <sys/resource.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace pnb::test {

struct ChildResult {
    int exitCode = -1;  // -1: did not exit normally
    std::string output; // stdout and stderr, interleaved
    double seconds = 0;
    uint64_t maxRssBytes = 0;
};

// Whether this build runs under AddressSanitizer (whose shadow memory needs an address space no
// RLIMIT_AS allows).
constexpr bool kAddressSanitizer =
#if defined(PNB_ASAN)
    true;
#else
    false;
#endif

// The time a run that should cost no more than the tool's start-up may take: twice a baseline
// run of the same tool on an ordinary input, plus a second. An absolute bound fails on a loaded
// machine; what it guards against (zero-filling a 4 GiB buffer) takes 15 s on an idle one.
inline double startupBound(const ChildResult& baseline) {
    return 2 * baseline.seconds + 1.0;
}

// Runs argv[0] with the arguments; `outputFile` receives its output. `addressSpaceLimit` > 0
// sets RLIMIT_AS in the child. LeakSanitizer is off in the child: OIIO's PNG reader leaks a
// string on every corrupt PNG (see texture_processing_test.cpp), which is not what is tested.
inline ChildResult runChild(const std::vector<std::string>& argv, const std::string& outputFile,
                            uint64_t addressSpaceLimit = 0) {
    ChildResult r;
    std::vector<char*> args;
    for (const std::string& a : argv)
        args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    const auto start = std::chrono::steady_clock::now();
    const pid_t pid = fork();
    if (pid == 0) {
        if (!std::freopen(outputFile.c_str(), "w", stdout) || dup2(fileno(stdout), 2) < 0)
            _exit(126);
        if (addressSpaceLimit > 0) {
            rlimit limit{addressSpaceLimit, addressSpaceLimit};
            if (setrlimit(RLIMIT_AS, &limit) != 0) _exit(126);
        }
        setenv("ASAN_OPTIONS", "detect_leaks=0", 1);
        execv(args[0], args.data());
        _exit(127);
    }
    if (pid < 0) return r;
    int status = 0;
    rusage usage{};
    if (wait4(pid, &status, 0, &usage) != pid) return r;
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    r.maxRssBytes = uint64_t(usage.ru_maxrss) * 1024; // Linux reports KiB
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::ifstream in(outputFile, std::ios::binary);
    r.output.assign(std::istreambuf_iterator<char>(in), {});
    return r;
}

} // namespace pnb::test
