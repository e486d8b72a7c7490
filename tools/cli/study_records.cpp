// Study run records as JSON (tools/cli/study_records.h), through Debian's nlohmann-json.
#include "tools/cli/study_records.h"

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/json_output.h"
#include "engine/core/log.h"

#include <cmath>
#include <limits>

namespace iblx::cli {

namespace {

// JSON has no NaN (an error below a Monte Carlo reference's noise): null.
nlohmann::json number(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}
double numberOf(const nlohmann::json& value) {
  return value.is_null() ? std::numeric_limits<double>::quiet_NaN() : value.get<double>();
}

}  // namespace

const char* runStatusName(RunStatus status) {
  switch (status) {
    case RunStatus::Done:
      return "done";
    case RunStatus::Skipped:
      return "skipped";
    case RunStatus::Failed:
      return "failed";
  }
  return "?";
}

void writeStudyRecord(const std::filesystem::path& path, const StudyRecord& r) {
  JsonObject json;
  json["id"] = r.id;
  json["scene"] = r.scene;
  json["method"] = r.method;
  json["sequence"] = r.sequence;
  json["seed"] = r.seed;
  json["status"] = runStatusName(r.status);
  json["message"] = r.message;
  json["device"] = r.device;
  json["host"] = r.host;
  json["seconds"] = r.seconds;
  json["label"] = r.run.method;
  json["setup_s"] = r.run.setupSeconds;
  json["final_max_abs_z"] = number(r.run.finalMaxAbsZ);
  json["non_finite_samples"] = r.run.nonFiniteSamples;
  json["finite_image"] = r.run.finiteImage;
  // Points as arrays: spp, gpu_s, wall_s, mse, relmse.
  nlohmann::json points = nlohmann::json::array();
  for (const auto& p : r.run.points)
    points.push_back({p.spp, p.gpuSeconds, p.wallSeconds, number(p.mse), number(p.relMse)});
  json["points"] = std::move(points);
  writeFileAtomically(path, json.dump() + "\n");
}

std::optional<StudyRecord> readStudyRecord(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return std::nullopt;
  try {
    const nlohmann::json json = nlohmann::json::parse(readInputText(path, 64u << 20));
    StudyRecord r;
    r.id = json.at("id").get<std::string>();
    r.scene = json.at("scene").get<std::string>();
    r.method = json.at("method").get<std::string>();
    r.sequence = json.at("sequence").get<std::string>();
    r.seed = json.at("seed").get<std::uint32_t>();
    const std::string status = json.at("status").get<std::string>();
    if (status == "done")
      r.status = RunStatus::Done;
    else if (status == "skipped")
      r.status = RunStatus::Skipped;
    else if (status == "failed")
      r.status = RunStatus::Failed;
    else
      throw Error("unknown status '" + status + "'");
    r.message = json.at("message").get<std::string>();
    r.device = json.at("device").get<std::string>();
    r.host = json.at("host").get<std::string>();
    r.seconds = json.at("seconds").get<double>();
    r.run.method = json.at("label").get<std::string>();
    r.run.sequence = r.sequence;
    r.run.seed = r.seed;
    r.run.setupSeconds = json.at("setup_s").get<double>();
    r.run.finalMaxAbsZ = numberOf(json.at("final_max_abs_z"));
    r.run.nonFiniteSamples = json.at("non_finite_samples").get<std::uint32_t>();
    r.run.finiteImage = json.at("finite_image").get<bool>();
    for (const auto& p : json.at("points")) {
      if (!p.is_array() || p.size() != 5) throw Error("a point is not [spp, gpu_s, wall_s, mse, relmse]");
      r.run.points.push_back({p[0].get<std::uint64_t>(), p[1].get<double>(), p[2].get<double>(),
                              numberOf(p[3]), numberOf(p[4])});
    }
    if (r.status == RunStatus::Done && r.run.points.empty()) throw Error("a finished run without points");
    return r;
  } catch (const std::exception& e) {
    warn(path.string() + ": " + e.what() + "; measuring its run again");
    return std::nullopt;
  }
}

bool runIsComplete(const std::optional<StudyRecord>& record) {
  return record && record->status != RunStatus::Failed;
}

}  // namespace iblx::cli
