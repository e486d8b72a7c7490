// Study plans (tools/cli/study_plan.h), read with Debian's toml++.
#include "tools/cli/study_plan.h"

#include "engine/core/cache_dir.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/file_lock.h"
#include "engine/core/hash.h"
#include "tools/cli/converge_scene.h"

#include <toml++/toml.h>

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <map>
#include <set>
#include <unistd.h>

namespace iblx::cli {

namespace fs = std::filesystem;

namespace {

// Keys that define a scene (converge's scene flags) and keys of the measurement (its measurement and
// reference flags); `methods` and `sequences` are --method and --seq, repeated.
const std::set<std::string> kSceneKeys = {"env",   "env_rotation", "brdf", "params", "object",
                                          "orbit", "zoom",         "size", "case"};
const std::set<std::string> kMeasurementKeys = {
    "methods",   "sequences",      "seeds",           "seed", "spp", "max_spp", "time", "points_per_octave",
    "reference", "reference_time", "reference_method"};
// Keys that say which runs exist rather than what a run does: not part of a scene's definition (each run's
// own method, sequence and seed are in its id).
const std::set<std::string> kRunListKeys = {"methods", "sequences", "seeds", "seed"};
// Keys whose relative paths are relative to the plan's folder.
const std::set<std::string> kPathKeys = {"env", "brdf", "object"};
constexpr const char* kInputsVariable = "${inputs}/";
constexpr const char* kPlanDirVariable = "${plan_dir}";

std::string location(const fs::path& file, const toml::node& node) {
  const auto line = node.source().begin.line;
  return file.string() + (line > 0 ? ":" + std::to_string(line) : std::string());
}

// A TOML scalar as a flag's value: numbers in their shortest round-trip form.
std::string scalarText(const fs::path& file, const std::string& key, const toml::node& node) {
  if (const auto* s = node.as_string()) return s->get();
  if (const auto* i = node.as_integer()) return std::to_string(i->get());
  if (const auto* f = node.as_floating_point()) {
    char text[64];
    const auto result = std::to_chars(text, text + sizeof text, f->get());
    return std::string(text, result.ptr);
  }
  throw Error(location(file, node) + ": " + key + ": expected a string or a number");
}

std::string dashed(std::string key) {
  std::replace(key.begin(), key.end(), '_', '-');
  return "--" + key;
}

// The values of one scene: later tables override earlier ones (plan defaults, env, material, scene).
using KeyValues = std::map<std::string, const toml::node*>;

void collectKeys(const fs::path& file, const toml::table& table, KeyValues& values, bool sceneLevel) {
  for (const auto& [key, node] : table) {
    const std::string name(key.str());
    if (kSceneKeys.count(name) || kMeasurementKeys.count(name))
      values[name] = &node;
    else if (sceneLevel && name != "name")
      throw Error(location(file, node) + ": unknown key '" + name +
                  "' (scene keys are converge's scene and measurement flags without the dashes, e.g. env, "
                  "brdf, params, size, methods, sequences, seeds, time, max_spp; docs/STUDIES.md)");
  }
}

// Appends the flags of one key; `literal` is the plan's text (ids), `flags` the one converge parses.
void appendFlags(const StudyPlan& plan, const std::string& key, const toml::node& node, Args& flags,
                 std::string& literal) {
  const auto add = [&](const std::string& flag, const std::string& value, const std::string& resolved) {
    flags.push_back(flag);
    flags.push_back(resolved);
    literal += " " + flag + " " + value;
  };
  if (key == "params") {
    const auto* table = node.as_table();
    if (!table)
      throw Error(location(plan.file, node) + ": params: expected a table, e.g. { roughness = 0.3 }");
    for (const auto& [name, value] : *table) {
      const std::string text = std::string(name.str()) + "=" + scalarText(plan.file, "params", value);
      add("--param", text, text);
    }
    return;
  }
  if (key == "methods" || key == "sequences") {
    const auto* array = node.as_array();
    if (!array) throw Error(location(plan.file, node) + ": " + key + ": expected an array of strings");
    for (const auto& item : *array) {
      const auto* s = item.as_string();
      if (!s) throw Error(location(plan.file, item) + ": " + key + ": expected an array of strings");
      add(key == "methods" ? "--method" : "--seq", s->get(), s->get());
    }
    return;
  }
  std::string value = scalarText(plan.file, key, node);
  if (key == "size" && node.is_integer()) value += "x" + value;
  std::string resolved = value;
  if (value.rfind(kInputsVariable, 0) == 0)
    resolved = (plan.directory / "inputs" / value.substr(std::string(kInputsVariable).size())).string();
  else if (kPathKeys.count(key) && fs::path(value).is_relative()) {
    std::error_code ec;
    const fs::path candidate = fs::absolute(plan.file).parent_path() / value;
    if (fs::exists(candidate, ec)) resolved = candidate.string();
  }
  add(dashed(key), value, resolved);
}

StudyScene makeScene(const StudyPlan& plan, const std::string& name, const KeyValues& values) {
  StudyScene scene;
  scene.name = name;
  for (const auto& [key, node] : values) {
    std::string literal;
    appendFlags(plan, key, *node, scene.flags, literal);
    if (!kRunListKeys.count(key)) scene.definition += literal;
  }
  // A generated input is defined by the command that writes it.
  for (const auto& input : plan.inputs)
    if (scene.definition.find(kInputsVariable + input.name) != std::string::npos) {
      scene.definition += " [" + input.name + ":";
      for (const auto& word : input.command) scene.definition += " " + word;
      if (!input.text.empty()) scene.definition += " text " + hexKey(ContentHash().add(input.text).value());
      scene.definition += "]";
    }
  return scene;
}

const toml::array* arrayOfTables(const fs::path& file, const toml::table& root, const char* key) {
  const toml::node* node = root.get(key);
  if (!node) return nullptr;
  const auto* array = node->as_array();
  if (!array || !array->is_array_of_tables())
    throw Error(location(file, *node) + ": '" + key + "' must be an array of tables ([[" + key + "]])");
  return array;
}

std::string requiredName(const fs::path& file, const toml::table& table, const char* what) {
  const auto* name = table.get_as<std::string>("name");
  if (!name || name->get().empty())
    throw Error(location(file, table) + ": every [[" + what + "]] needs a name");
  const std::string& text = name->get();
  if (text.find_first_of("/\\") != std::string::npos || text == "." || text == "..")
    throw Error(location(file, *name) + ": name '" + text + "': a folder name, without '/'");
  return text;
}

std::vector<std::string> stringList(const fs::path& file, const toml::table& table, const char* key) {
  std::vector<std::string> list;
  const toml::node* node = table.get(key);
  if (!node) return list;
  const auto* array = node->as_array();
  if (!array) throw Error(location(file, *node) + ": " + key + ": expected an array of strings");
  for (const auto& item : *array) {
    const auto* s = item.as_string();
    if (!s) throw Error(location(file, item) + ": " + key + ": expected an array of strings");
    list.push_back(s->get());
  }
  return list;
}

// MurmurHash3's 64-bit finalizer (Appleby, smhasher): FNV-1a leaves ids of definitions that differ in their
// last character differing in a few digits; mixed, every digit of an id depends on every byte.
std::uint64_t mixBits(std::uint64_t h) {
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdull;
  h ^= h >> 33;
  h *= 0xc4ceb9fe1a85ec53ull;
  h ^= h >> 33;
  return h;
}

// While alive, standard output goes to standard error: a generator's report must not mix with `study plan`'s
// listing.
class StdoutToStderr {
 public:
  StdoutToStderr() {
    std::fflush(stdout);
    saved_ = ::dup(STDOUT_FILENO);
    if (saved_ >= 0) ::dup2(STDERR_FILENO, STDOUT_FILENO);
  }
  ~StdoutToStderr() {
    std::fflush(stdout);
    if (saved_ >= 0) ::dup2(saved_, STDOUT_FILENO), ::close(saved_);
  }
  StdoutToStderr(const StdoutToStderr&) = delete;
  StdoutToStderr& operator=(const StdoutToStderr&) = delete;

 private:
  int saved_ = -1;
};

}  // namespace

StudyPlan readStudyPlan(const fs::path& file) {
  StudyPlan plan;
  plan.file = file;
  toml::table root;
  try {
    root = toml::parse(readInputText(file, 16u << 20), file.string());
  } catch (const toml::parse_error& e) {
    throw Error(file.string() + ":" + std::to_string(e.source().begin.line) + ": " +
                std::string(e.description()));
  }
  static const std::set<std::string> kPlanKeys = {"title", "directory", "report_directory", "target_relmse",
                                                  "input", "map",       "material",         "sizes",
                                                  "scene", "report"};
  for (const auto& [key, node] : root) {
    const std::string name(key.str());
    if (!kPlanKeys.count(name) && !kSceneKeys.count(name) && !kMeasurementKeys.count(name))
      throw Error(location(file, node) + ": unknown key '" + name +
                  "' (docs/STUDIES.md lists a plan's keys)");
  }
  plan.title = root["title"].value_or(file.stem().string());
  const fs::path base = fs::absolute(file).parent_path();
  const std::string directory = root["directory"].value_or(std::string());
  if (directory.empty()) throw Error(file.string() + ": no 'directory' (where the runs' results go)");
  plan.directory = fs::weakly_canonical(base / directory);
  const std::string report = root["report_directory"].value_or(std::string());
  plan.reportDirectory = report.empty() ? plan.directory : fs::weakly_canonical(base / report);
  if (const toml::node* target = root.get("target_relmse")) {
    const auto value = target->value<double>();
    if (!value || !(*value > 0))
      throw Error(location(file, *target) + ": target_relmse: expected a number > 0");
    plan.targetRelMse = *value;
  }
  if (const toml::node* node = root.get("report")) {
    const auto* table = node->as_table();
    if (!table) throw Error(location(file, *node) + ": report: expected a table");
    if (table->contains("plots")) plan.plots = stringList(file, *table, "plots");
    if (table->contains("heat_maps")) plan.heatMaps = stringList(file, *table, "heat_maps");
    plan.decomposeAgainst = (*table)["decompose_against"].value_or(std::string());
    for (const auto& [key, value] : *table)
      if (key.str() != "plots" && key.str() != "heat_maps" && key.str() != "decompose_against")
        throw Error(location(file, value) + ": unknown key 'report." + std::string(key.str()) +
                    "' (plots, heat_maps, decompose_against)");
  }
  if (const auto* inputs = arrayOfTables(file, root, "input"))
    for (const auto& node : *inputs) {
      const auto& table = *node.as_table();
      StudyInput input{requiredName(file, table, "input"), stringList(file, table, "command"),
                       table["text"].value_or(std::string())};
      static const std::set<std::string> kGenerators = {"merl-synth", "measured-synth", "make-sky",
                                                        "make-teapot"};
      if (input.command.empty() == input.text.empty())
        throw Error(location(file, table) + ": input " + input.name + ": give a command or a text");
      if (!input.command.empty() && !kGenerators.count(input.command.front()))
        throw Error(location(file, table) + ": input " + input.name +
                    ": command must start with merl-synth, measured-synth, make-sky or make-teapot");
      plan.inputs.push_back(std::move(input));
    }

  KeyValues defaults;
  collectKeys(file, root, defaults, false);
  // The grid: every [[map]] x [[material]] (x sizes), in plan order.
  const auto* envs = arrayOfTables(file, root, "map");
  const auto* materials = arrayOfTables(file, root, "material");
  if (bool(envs) != bool(materials))
    throw Error(file.string() + ": a grid needs both [[map]] and [[material]] tables");
  std::vector<std::string> sizes = stringList(file, root, "sizes");
  if (envs)
    for (const auto& envNode : *envs) {
      const auto& envTable = *envNode.as_table();
      const std::string envName = requiredName(file, envTable, "map");
      for (const auto& materialNode : *materials) {
        const auto& materialTable = *materialNode.as_table();
        const std::string materialName = requiredName(file, materialTable, "material");
        KeyValues values = defaults;
        collectKeys(file, envTable, values, true);
        collectKeys(file, materialTable, values, true);
        if (sizes.empty()) {
          plan.scenes.push_back(makeScene(plan, envName + "-" + materialName, values));
          continue;
        }
        for (const auto& size : sizes) {
          StudyScene scene = makeScene(plan, envName + "-" + materialName + "-" + size, values);
          std::string literal;
          appendFlags(plan, "size", *toml::value<std::string>(size).as_string(), scene.flags, literal);
          scene.definition += literal;
          plan.scenes.push_back(std::move(scene));
        }
      }
    }
  if (const auto* scenes = arrayOfTables(file, root, "scene"))
    for (const auto& node : *scenes) {
      const auto& table = *node.as_table();
      KeyValues values = defaults;
      collectKeys(file, table, values, true);
      plan.scenes.push_back(makeScene(plan, requiredName(file, table, "scene"), values));
    }
  if (plan.scenes.empty())
    throw Error(file.string() + ": no scenes ([[scene]], or [[map]] and [[material]])");
  std::set<std::string> names;
  for (const auto& scene : plan.scenes)
    if (!names.insert(scene.name).second) throw Error(file.string() + ": two scenes are named " + scene.name);
  return plan;
}

void prepareStudyInputs(const StudyPlan& plan) {
  for (const auto& input : plan.inputs) {
    const fs::path path = plan.directory / "inputs" / input.name;
    std::error_code ec;
    if (fs::exists(path, ec)) continue;
    FileLock lock(plan.directory / "inputs" / (input.name + ".lock"), "the input " + input.name);
    if (fs::exists(path, ec)) continue;  // written while this task waited
    // Written beside its final name with the same extension (the commands choose the format by it), then
    // renamed: a reader never sees a partial input.
    const fs::path temporary =
        plan.directory / "inputs" / (".tmp-" + std::to_string(::getpid()) + "-" + input.name);
    Args args;
    // ${plan_dir}: the plan's folder, so a command can name a file of the repository wherever it runs.
    const std::string planDir = fs::absolute(plan.file).parent_path().string();
    for (std::size_t i = 1; i < input.command.size(); ++i) {
      std::string word = input.command[i];
      for (auto at = word.find(kPlanDirVariable); at != std::string::npos; at = word.find(kPlanDirVariable))
        word.replace(at, std::string(kPlanDirVariable).size(), planDir);
      args.push_back(word);
    }
    args.push_back("--out");
    args.push_back(temporary.string());
    std::fprintf(stderr, "study: writing input %s\n", input.name.c_str());
    try {
      StdoutToStderr quiet;
      if (!input.text.empty())
        writeFileAtomically(path, input.text);
      else if (runCommand(input.command.front(), args) != 0)
        throw Error("it exited with an error");
      else
        fs::rename(temporary, path);
    } catch (const std::exception& e) {
      fs::remove(temporary, ec);
      throw Error(plan.file.string() + ": input " + input.name + ": " + e.what());
    }
  }
}

std::vector<StudyRun> listStudyRuns(const StudyPlan& plan) {
  std::vector<StudyRun> runs;
  for (std::size_t s = 0; s < plan.scenes.size(); ++s) {
    const StudyScene& scene = plan.scenes[s];
    ConvergeSceneFlags flags;
    std::vector<std::string> methods;
    try {
      ArgParser parser("study");
      addConvergeSceneFlags(parser, flags);
      parser.parse(scene.flags);
      finishConvergeSceneFlags(flags);
      const LoadedBrdf brdf = checkConvergeScene(flags);
      methods = flags.spec.methods;
      if (methods.empty())
        for (const auto& m : defaultMethodSpecs(*brdf.info)) methods.push_back(m.method);
    } catch (const Error& e) {
      throw Error(plan.file.string() + ": scene " + scene.name + ": " + e.what());
    }
    std::vector<std::string> sequences = flags.spec.sequences;
    if (sequences.empty())
      for (const auto& q : sequenceRegistry()) sequences.push_back(q.name);
    const std::vector<std::uint32_t> seeds = seedList(flags.spec);
    // Sequence by sequence, as `converge` runs them, so a scene's summary and figures come in its order.
    for (const auto& sequence : sequences)
      for (const auto& method : methods)
        for (const std::uint32_t seed : seeds) {
          StudyRun run{"", s, method, sequence, seed, seed == seeds.front()};
          ContentHash hash;
          hash.add(scene.definition).add(std::string_view("\n")).add(method);
          hash.add(std::string_view("\n"))
              .add(sequence)
              .add(std::string_view("\n"))
              .add(std::to_string(seed));
          run.id = hexKey(mixBits(hash.value()));
          runs.push_back(std::move(run));
        }
  }
  std::set<std::string> ids;
  for (const auto& run : runs)
    if (!ids.insert(run.id).second)
      throw Error(plan.file.string() + ": two runs are the same (scene " + plan.scenes[run.scene].name +
                  ", " + run.method + "/" + run.sequence + ", seed " + std::to_string(run.seed) +
                  "): two scenes with the same definition, or a method listed twice");
  return runs;
}

std::optional<std::string> sceneFlag(const StudyScene& scene, std::string_view flag) {
  std::optional<std::string> value;
  for (std::size_t i = 0; i + 1 < scene.flags.size(); ++i)
    if (scene.flags[i] == flag) value = scene.flags[i + 1];
  return value;
}

std::optional<double> sceneTimeBudget(const StudyScene& scene) {
  const std::optional<std::string> time = sceneFlag(scene, "--time");
  if (!time) return std::nullopt;
  try {
    return parseDouble("--time", *time, 1e-3, 1e6);
  } catch (const Error&) {
    return std::nullopt;  // reported where the flags are parsed
  }
}

StudyShard parseStudyShard(const std::string& text) {
  const auto slash = text.find('/');
  StudyShard shard;
  try {
    if (slash == std::string::npos) throw Error("");
    shard.index = parseUint("--shard", text.substr(0, slash), 1, 1u << 20);
    shard.count = parseUint("--shard", text.substr(slash + 1), 1, 1u << 20);
  } catch (const Error&) {
    throw Error("--shard " + text + ": expected I/N with 1 <= I <= N, e.g. 2/4");
  }
  if (shard.index > shard.count) throw Error("--shard " + text + ": expected I/N with 1 <= I <= N, e.g. 2/4");
  return shard;
}

std::vector<StudyRun> shardOf(const std::vector<StudyRun>& runs, StudyShard shard) {
  const std::size_t begin = runs.size() * (shard.index - 1) / shard.count;
  const std::size_t end = runs.size() * shard.index / shard.count;
  return {runs.begin() + std::ptrdiff_t(begin), runs.begin() + std::ptrdiff_t(end)};
}

fs::path runRecordPath(const StudyPlan& plan, const StudyRun& run) {
  return plan.directory / "runs" / (run.id + ".json");
}

fs::path runImagePath(const StudyPlan& plan, const StudyRun& run) {
  return plan.directory / "runs" / (run.id + ".exr");
}

fs::path sceneDataDirectory(const StudyPlan& plan, const StudyScene& scene) {
  return plan.directory / "scenes" / scene.name;
}

}  // namespace iblx::cli
