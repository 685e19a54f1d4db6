// kiloloop_fuzz: runs the seeded fuzz targets, each in a child process so that a crash (a signal,
// or a sanitizer abort) is counted and reported with the input that caused it instead of ending
// the run. Prints one line per target: inputs, bad inputs, bad outputs, missed statuses, crashes.
//
//   kiloloop_fuzz [--target NAME|all] [--inputs N] [--seed S]
//
// Exit 0 when every target ran without crashes, bad outputs or missed statuses; 77 (ctest's skip)
// when a single target's only findings are known defects of code outside this harness's reach.
#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "fuzz_common.hpp"

namespace {

using kiloloop::fuzz::Tally;
using kiloloop::fuzz::TargetFn;

struct Target {
  const char* name;
  TargetFn fn;
};

const Target kTargets[] = {
    {"qp", kiloloop::fuzz::fuzz_qp},
    {"computed_torque", kiloloop::fuzz::fuzz_computed_torque},
    {"joint_pd_gravity", kiloloop::fuzz::fuzz_joint_pd_gravity},
    {"cartesian_tracking", kiloloop::fuzz::fuzz_cartesian_tracking},
    {"cartesian_impedance", kiloloop::fuzz::fuzz_cartesian_impedance},
    {"hybrid_force_position", kiloloop::fuzz::fuzz_hybrid_force_position},
    {"arm_supervisor", kiloloop::fuzz::fuzz_arm_supervisor},
    {"quadruped", kiloloop::fuzz::fuzz_quadruped},
    {"aerial", kiloloop::fuzz::fuzz_aerial},
};

// What a child hands back through shared memory.
struct Shared {
  volatile std::uint64_t progress;  // index of the input being run
  Tally tally;
  int done;
};

int usage() {
  std::fprintf(stderr, "usage: kiloloop_fuzz [--target NAME|all] [--inputs N] [--seed S]\ntargets:");
  for (const Target& t : kTargets) std::fprintf(stderr, " %s", t.name);
  std::fprintf(stderr, "\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::string which = "all";
  std::uint64_t inputs = 1000000, seed = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc) return usage();
    if (a == "--target") which = argv[++i];
    else if (a == "--inputs") inputs = std::strtoull(argv[++i], nullptr, 10);
    else if (a == "--seed") seed = std::strtoull(argv[++i], nullptr, 10);
    else return usage();
  }
  std::vector<const Target*> run;
  for (const Target& t : kTargets)
    if (which == "all" || which == t.name) run.push_back(&t);
  if (run.empty()) return usage();

  auto* shared = static_cast<Shared*>(mmap(nullptr, sizeof(Shared), PROT_READ | PROT_WRITE,
                                           MAP_SHARED | MAP_ANONYMOUS, -1, 0));
  if (shared == MAP_FAILED) return 3;
  int failures = 0;
  std::uint64_t known = 0;
  std::printf("kiloloop_fuzz: seed %llu, %llu inputs per target\n",
              static_cast<unsigned long long>(seed), static_cast<unsigned long long>(inputs));
  std::printf("%-22s %10s %10s %11s %13s %7s %7s %8s\n", "target", "inputs", "bad_inputs",
              "bad_outputs", "missed_status", "known", "crashes", "time_s");
  std::fflush(stdout);
  for (const Target* t : run) {
    std::memset(static_cast<void*>(shared), 0, sizeof(Shared));
    const auto t0 = std::chrono::steady_clock::now();
    const pid_t pid = fork();
    if (pid == 0) {
      shared->tally = t->fn(seed, inputs, &shared->progress);
      shared->done = 1;
      std::fflush(stdout);
      _exit(0);
    }
    int wstatus = 0;
    waitpid(pid, &wstatus, 0);
    const double secs =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const bool crashed = !shared->done || !WIFEXITED(wstatus) || WEXITSTATUS(wstatus) != 0;
    const Tally& r = shared->tally;
    std::printf("%-22s %10llu %10llu %11llu %13llu %7llu %7d %8.1f\n", t->name,
                static_cast<unsigned long long>(crashed ? shared->progress : r.inputs),
                static_cast<unsigned long long>(r.bad_inputs),
                static_cast<unsigned long long>(r.bad_outputs),
                static_cast<unsigned long long>(r.missed_status),
                static_cast<unsigned long long>(r.known_failures), crashed ? 1 : 0, secs);
    if (crashed) {
      std::printf("  [%s] CRASH at input #%llu (seed %llu): %s %d; rerun with --target %s --seed "
                  "%llu --inputs %llu\n",
                  t->name, static_cast<unsigned long long>(shared->progress),
                  static_cast<unsigned long long>(seed),
                  WIFSIGNALED(wstatus) ? "signal" : "exit status",
                  WIFSIGNALED(wstatus) ? WTERMSIG(wstatus) : WEXITSTATUS(wstatus), t->name,
                  static_cast<unsigned long long>(seed),
                  static_cast<unsigned long long>(shared->progress + 1));
    }
    std::fflush(stdout);
    if (crashed || r.bad_outputs > 0 || r.missed_status > 0) ++failures;
    known += crashed ? 0 : r.known_failures;
  }
  if (failures == 0 && known > 0) {
    std::printf("KNOWN-FAILING (skipped): %llu findings in code this harness does not fix; see the "
                "KNOWN lines above and the target's source for the defects\n",
                static_cast<unsigned long long>(known));
    return run.size() == 1 ? 77 : 0;  // 77: ctest's skip code for a single-target run
  }
  return failures == 0 ? 0 : 1;
}
