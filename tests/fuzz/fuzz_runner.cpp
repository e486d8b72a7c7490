// iblx_fuzz: the deterministic mutation runner over the fuzz targets of tests/fuzz/fuzz_target.h. It needs no
// libFuzzer (any compiler builds it) and replays exactly from its seed. Per target it runs the seeds and the
// saved regression inputs, then --iterations mutated inputs; an input whose outcome (accepted, or the
// reader's error message with numbers and paths removed) is new joins the corpus, a cheap stand-in for
// coverage feedback. Findings (an exception other than iblx::Error, a crash, a sanitizer report, an input
// over --timeout) are saved to --findings DIR and make the exit status non-zero.
//
//   iblx_fuzz --target all --iterations 2000 --seed 1 [--seconds 10] [--regressions DIR] [--corpus-out DIR]
//   iblx_fuzz --target exr --replay FILE...     # reproduce a finding
//   iblx_fuzz --list
#include "tests/fuzz/fuzz_target.h"
#include "tests/fuzz/mutator.h"

#include "engine/core/error.h"
#include "engine/core/log.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

// AddressSanitizer's hook, present only in sanitized builds: it runs before a report ends the process.
extern "C" void __sanitizer_set_death_callback(void (*callback)(void)) __attribute__((weak));

namespace iblx::fuzz {

namespace {

struct Options {
  std::vector<std::string> targets;
  long iterations = 1000;
  std::uint64_t seed = 1;
  double seconds = 0.0;   // per target; 0: no limit
  unsigned timeout = 30;  // per input, seconds
  std::size_t maxBytes = 1 << 20;
  std::filesystem::path regressions, corpusOut, findings = ".";
  std::vector<std::filesystem::path> replay;
  bool list = false;
};

[[noreturn]] void usage(const std::string& problem) {
  std::cerr
      << "iblx_fuzz: " << problem
      << "\nusage: iblx_fuzz --target NAME|all [--iterations N] [--seed S] [--seconds T] [--timeout T]\n"
         "                 [--max-bytes N] [--regressions DIR] [--corpus-out DIR] [--findings DIR]\n"
         "       iblx_fuzz --target NAME --replay FILE...\n"
         "       iblx_fuzz --list\n";
  std::exit(2);
}

Options parseOptions(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) usage(flag + " needs a value");
      return argv[++i];
    };
    try {
      if (flag == "--target") {
        const std::string list = value();
        for (std::size_t at = 0; at <= list.size();) {
          const std::size_t comma = std::min(list.find(',', at), list.size());
          o.targets.push_back(list.substr(at, comma - at));
          at = comma + 1;
        }
      } else if (flag == "--iterations") {
        o.iterations = std::stol(value());
      } else if (flag == "--seed") {
        o.seed = std::stoull(value());
      } else if (flag == "--seconds") {
        o.seconds = std::stod(value());
      } else if (flag == "--timeout") {
        o.timeout = unsigned(std::stoul(value()));
      } else if (flag == "--max-bytes") {
        o.maxBytes = std::stoul(value());
      } else if (flag == "--regressions") {
        o.regressions = value();
      } else if (flag == "--corpus-out") {
        o.corpusOut = value();
      } else if (flag == "--findings") {
        o.findings = value();
      } else if (flag == "--replay") {
        while (i + 1 < argc && std::string_view(argv[i + 1]).substr(0, 2) != "--")
          o.replay.push_back(argv[++i]);
      } else if (flag == "--list") {
        o.list = true;
      } else {
        usage("unknown flag " + flag);
      }
    } catch (const std::logic_error&) {  // std::stol and friends
      usage(flag + ": not a number");
    }
  }
  return o;
}

Bytes readFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path.string());
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeFile(const std::filesystem::path& path, const Bytes& bytes) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

// ---- What a crash leaves behind ---------------------------------------------------------------------------
// A crash, a sanitizer report or a timeout ends the process inside the reader, so the input being run and
// the file it goes to are kept where an async-signal-safe handler can write them out.

struct CurrentInput {
  const std::uint8_t* data = nullptr;
  std::size_t size = 0;
  char path[4096] = {};
};
CurrentInput gCurrent;

void saveCurrentInput() {
  if (gCurrent.data == nullptr) return;
  const int fd = ::open(gCurrent.path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0) return;
  for (std::size_t at = 0; at < gCurrent.size;) {
    const ssize_t n = ::write(fd, gCurrent.data + at, gCurrent.size - at);
    if (n <= 0) break;
    at += std::size_t(n);
  }
  ::close(fd);
  const char note[] = "\niblx_fuzz: the input is saved as ";
  [[maybe_unused]] ssize_t ignored = ::write(2, note, sizeof note - 1);
  ignored = ::write(2, gCurrent.path, std::strlen(gCurrent.path));
  ignored = ::write(2, "\n", 1);
}

void onFatalSignal(int signal) {
  const char hang[] = "\niblx_fuzz: FINDING: an input ran past --timeout (a hang?)";
  const char crash[] = "\niblx_fuzz: FINDING: a fatal signal (a crash) while reading an input";
  [[maybe_unused]] const ssize_t ignored =
      signal == SIGALRM ? ::write(2, hang, sizeof hang - 1) : ::write(2, crash, sizeof crash - 1);
  saveCurrentInput();
  ::signal(signal, SIG_DFL);
  ::raise(signal == SIGALRM ? SIGABRT : signal);
}

void installCrashHandlers() {
  for (int s : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGALRM}) ::signal(s, onFatalSignal);
  if (__sanitizer_set_death_callback) __sanitizer_set_death_callback(saveCurrentInput);
}

// ---- Running one target -----------------------------------------------------------------------------------

// The outcome of one input: "ok", or the reader's message with the scratch path and numbers removed, so that
// inputs failing the same check share an outcome.
std::string outcomeOf(const std::string& message) {
  std::string text = message;
  const std::string scratch = scratchDirectory().string();
  for (std::size_t at; (at = text.find(scratch)) != std::string::npos;) text.erase(at, scratch.size());
  std::string out;
  for (char c : text) {
    if (std::isdigit(static_cast<unsigned char>(c))) {
      if (out.empty() || out.back() != '#') out.push_back('#');
    } else {
      out.push_back(c);
    }
    if (out.size() >= 96) break;
  }
  return out;
}

struct TargetReport {
  long executions = 0, accepted = 0, findings = 0;
  std::size_t seeds = 0, seedsAccepted = 0, regressions = 0, corpus = 0, outcomes = 0;
  double seconds = 0.0;
};

class TargetRun {
 public:
  TargetRun(const FuzzTarget& target, const Options& options) : target_(target), options_(options) {}

  // Runs one input; returns its outcome, or an empty string for a finding (reported and saved).
  std::string execute(const Bytes& input, const std::string& label) {
    const std::string path =
        (options_.findings / ("crash-" + std::string(target_.name) + "-" + label)).string();
    std::snprintf(gCurrent.path, sizeof gCurrent.path, "%s", path.c_str());
    gCurrent.data = input.data();
    gCurrent.size = input.size();
    ::alarm(options_.timeout);
    std::string outcome, finding;
    try {
      target_.run(input);
      outcome = "ok";
    } catch (const Error& e) {
      outcome = outcomeOf(e.what());
    } catch (const std::exception& e) {
      finding = std::string("an exception that is not iblx::Error escaped: ") + e.what();
    } catch (...) {
      finding = "an exception of unknown type escaped";
    }
    ::alarm(0);
    gCurrent.data = nullptr;
    ++report_.executions;
    if (outcome == "ok") ++report_.accepted;
    if (!finding.empty()) {
      ++report_.findings;
      const auto saved = options_.findings / ("finding-" + std::string(target_.name) + "-" + label);
      writeFile(saved, input);
      std::cerr << "iblx_fuzz: FINDING in " << target_.name << " (" << label << "): " << finding
                << "\n  input saved as " << saved.string() << "\n";
    }
    return outcome;
  }

  TargetReport run() {
    const auto start = std::chrono::steady_clock::now();
    std::vector<Bytes> corpus = target_.seeds();
    report_.seeds = corpus.size();
    for (std::size_t i = 0; i < corpus.size(); ++i) {
      const std::string outcome = execute(corpus[i], "seed-" + std::to_string(i));
      keep(outcome);
      if (outcome == "ok") ++report_.seedsAccepted;
    }
    // Regression inputs: files named TARGET-* (inputs that once were findings, kept so they stay fixed).
    if (!options_.regressions.empty() && std::filesystem::is_directory(options_.regressions)) {
      std::vector<std::filesystem::path> files;
      for (const auto& entry : std::filesystem::directory_iterator(options_.regressions))
        if (entry.path().filename().string().rfind(std::string(target_.name) + "-", 0) == 0)
          files.push_back(entry.path());
      std::sort(files.begin(), files.end());
      for (const auto& file : files) {
        Bytes input = readFile(file);
        keep(execute(input, file.filename().string()));
        corpus.push_back(std::move(input));
        ++report_.regressions;
      }
    }
    if (corpus.empty()) corpus.emplace_back();
    // Each target has its own stream, so adding a target never changes another one's inputs.
    std::uint64_t nameHash = 0;
    for (char c : target_.name) nameHash = nameHash * 131 + std::uint8_t(c);
    SplitMix64 rng(options_.seed ^ (nameHash * 0x9e3779b97f4a7c15ull));
    // An expensive target runs fewer inputs, but at least one unless none were asked for.
    const long iterations =
        options_.iterations <= 0 ? 0 : std::max(1L, long(double(options_.iterations) / target_.relativeCost));
    for (long i = 0; i < iterations; ++i) {
      if (options_.seconds > 0.0 && elapsed(start) > options_.seconds) break;
      Bytes input = mutate(corpus[rng.below(corpus.size())], corpus, rng, options_.maxBytes);
      if (keep(execute(input, "iteration-" + std::to_string(i))) && corpus.size() < 1024)
        corpus.push_back(std::move(input));
    }
    report_.corpus = corpus.size();
    report_.outcomes = outcomes_.size();
    report_.seconds = elapsed(start);
    if (!options_.corpusOut.empty())
      for (std::size_t i = 0; i < corpus.size(); ++i)
        writeFile(options_.corpusOut / std::string(target_.name) / ("input-" + std::to_string(i)), corpus[i]);
    return report_;
  }

 private:
  static double elapsed(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  // True for an outcome not seen before (the input joins the corpus); false for a finding.
  bool keep(const std::string& outcome) { return !outcome.empty() && outcomes_.insert(outcome).second; }

  const FuzzTarget& target_;
  const Options& options_;
  TargetReport report_;
  std::set<std::string> outcomes_;
};

}  // namespace

int runFuzzer(int argc, char** argv) {
  const Options options = parseOptions(argc, argv);
  if (options.list) {
    for (const FuzzTarget& t : fuzzTargets()) std::cout << t.name << "\t" << t.description << "\n";
    return 0;
  }
  if (options.targets.empty()) usage("no --target given");
  std::vector<const FuzzTarget*> targets;
  for (const std::string& name : options.targets) {
    if (name == "all") {
      for (const FuzzTarget& t : fuzzTargets()) targets.push_back(&t);
    } else if (const FuzzTarget* t = findFuzzTarget(name)) {
      targets.push_back(t);
    } else {
      usage("unknown target '" + name + "' (--list names them)");
    }
  }
  // Readers warn about what they repair (NaN texels, zero-area faces): expected here, and thousands of lines.
  long warnings = 0;
  setWarningSink([&](const std::string&) { ++warnings; });
  installCrashHandlers();
  std::filesystem::create_directories(options.findings);

  if (!options.replay.empty()) {
    if (targets.size() != 1) usage("--replay needs exactly one --target");
    int findings = 0;
    for (const auto& file : options.replay) {
      TargetRun run(*targets.front(), options);
      const std::string outcome = run.execute(readFile(file), file.filename().string());
      std::cout << file.string() << ": " << (outcome.empty() ? "FINDING" : outcome) << "\n";
      findings += outcome.empty();
    }
    return findings > 0 ? 1 : 0;
  }

  long findings = 0;
  std::printf("%-16s %10s %9s %10s %7s %9s %8s %9s\n", "target", "executions", "seconds", "exec/s", "seeds",
              "accepted", "corpus", "findings");
  for (const FuzzTarget* target : targets) {
    const TargetReport r = TargetRun(*target, options).run();
    std::printf("%-16s %10ld %9.2f %10.0f %3zu/%-3zu %9ld %8zu %9ld\n", std::string(target->name).c_str(),
                r.executions, r.seconds, double(r.executions) / std::max(r.seconds, 1e-9), r.seedsAccepted,
                r.seeds, r.accepted, r.corpus, r.findings);
    std::fflush(stdout);
    findings += r.findings;
  }
  std::printf("%ld findings (seed %llu)\n", findings, static_cast<unsigned long long>(options.seed));
  return findings > 0 ? 1 : 0;
}

}  // namespace iblx::fuzz

int main(int argc, char** argv) {
  return iblx::fuzz::runFuzzer(argc, argv);
}
