// Starting a child process from a launcher that holds memory: fork() + execve(), what
// retreat-launch did until 2026-12-06 (the baseline, measured in the same run), against
// ChildProcess, which starts its child with clone(CLONE_VM | CLONE_VFORK). Each iteration starts
// /bin/true, writes one byte into every page of the parent's working set (a launcher goes on
// working between two starts: after fork() each first write to a page is a copy-on-write fault),
// and reaps the child. Argument: the working set in MiB.

#include <benchmark/benchmark.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstddef>
#include <cstdlib>
#include <vector>

#include "retreat/launch/child_process.hpp"

namespace {

constexpr std::size_t page = 4096;

/// The parent's working set, written once so that it is resident before the timing.
std::vector<char> working_set(const benchmark::State& state) {
  return std::vector<char>(static_cast<std::size_t>(state.range(0)) * 1024 * 1024, 1);
}

void touch(std::vector<char>& memory) {
  for (std::size_t i = 0; i < memory.size(); i += page) ++memory[i];
  benchmark::DoNotOptimize(memory.data());
}

void BM_ForkExec(benchmark::State& state) {
  auto memory = working_set(state);
  char true_path[] = "/bin/true";
  char* const argv[] = {true_path, nullptr};
  for (auto _ : state) {
    const pid_t pid = ::fork();
    if (pid == 0) {
      ::execv(argv[0], argv);
      ::_exit(127);
    }
    touch(memory);
    int status = 0;
    ::waitpid(pid, &status, 0);
    if (pid < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
      state.SkipWithError("fork + exec of /bin/true failed");
      break;
    }
  }
}

void BM_ChildProcess(benchmark::State& state) {
  auto memory = working_set(state);
  for (auto _ : state) {
    retreat::launch::ChildProcess child("true", {"/bin/true"}, "/dev/null");
    touch(memory);
    while (child.running()) ::usleep(100);
    if (child.poll()->code != 0) {
      state.SkipWithError("ChildProcess of /bin/true failed");
      break;
    }
  }
}

BENCHMARK(BM_ForkExec)->Arg(0)->Arg(16)->Arg(64)->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK(BM_ChildProcess)->Arg(0)->Arg(16)->Arg(64)->Unit(benchmark::kMicrosecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
