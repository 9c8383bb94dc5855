#include "ricci/batch/results_log.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "ricci/errors.hpp"
#include "ricci/mesh/io.hpp"

namespace ricci {

namespace {

nlohmann::json number_or_null(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

double number_or_nan(const nlohmann::json& j, const char* name) {
  const auto it = j.find(name);
  if (it == j.end() || !it->is_number()) return std::numeric_limits<double>::quiet_NaN();
  return it->get<double>();
}

}  // namespace

const char* mesh_outcome_name(MeshOutcome outcome) {
  return enum_name(outcome, "internal_error");
}

MeshOutcome parse_mesh_outcome(const std::string& name) {
  if (const std::optional<MeshOutcome> outcome = find_enum<MeshOutcome>(name)) return *outcome;
  throw InvalidInput("unknown mesh outcome '" + name + "'");
}

std::string to_json_line(const MeshRecord& r) {
  nlohmann::json j;
  j["key"] = r.key;
  j["input"] = r.input;
  j["input_hash"] = r.input_hash;
  j["input_stamp"] = r.input_stamp;
  j["options"] = r.options;
  j["outcome"] = mesh_outcome_name(r.outcome);
  j["exit_code"] = r.exit_code;
  j["signal"] = r.signal;
  j["seconds"] = r.seconds;
  j["peak_memory_kb"] = r.peak_memory_kb;
  j["message"] = r.message;
  j["output"] = r.output;
  j["report"] = r.report;
  j["area_distortion"] = number_or_null(r.area_distortion);
  j["angle_distortion"] = number_or_null(r.angle_distortion);
  j["flipped_faces"] = r.flipped_faces;
  j["cones"] = r.cones;
  j["worker"] = r.worker;
  j["finished_at"] = r.finished_at;
  j["version"] = r.version;
  // Invalid UTF-8 in a message (a binary file name, a child's garbled stderr) is replaced, never
  // a reason to lose the record.
  return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

MeshRecord parse_mesh_record(const std::string& line) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(line);
  } catch (const nlohmann::json::exception& e) {
    throw InvalidInput(std::string("not a JSON line: ") + e.what());
  }
  if (!j.is_object() || !j.contains("key") || !j.contains("outcome")) {
    throw InvalidInput("not a batch record (no key or outcome)");
  }
  MeshRecord r;
  try {
    r.key = j.at("key").get<std::string>();
    r.input = j.value("input", "");
    r.input_hash = j.value("input_hash", "");
    r.input_stamp = j.value("input_stamp", "");
    r.options = j.value("options", std::vector<std::string>{});
    r.outcome = parse_mesh_outcome(j.at("outcome").get<std::string>());
    r.exit_code = j.value("exit_code", -1);
    r.signal = j.value("signal", 0);
    r.seconds = j.value("seconds", 0.0);
    r.peak_memory_kb = j.value("peak_memory_kb", 0L);
    r.message = j.value("message", "");
    r.output = j.value("output", "");
    r.report = j.value("report", "");
    r.area_distortion = number_or_nan(j, "area_distortion");
    r.angle_distortion = number_or_nan(j, "angle_distortion");
    r.flipped_faces = j.value("flipped_faces", -1);
    r.cones = j.value("cones", -1);
    r.worker = j.value("worker", "");
    r.finished_at = j.value("finished_at", "");
    r.version = j.value("version", "");
  } catch (const nlohmann::json::exception& e) {
    throw InvalidInput(std::string("a batch record field has the wrong type: ") + e.what());
  }
  return r;
}

ResultsLogContents read_results_log(const std::string& path) {
  ResultsLogContents contents;
  std::error_code missing;
  if (!std::filesystem::exists(path, missing)) return contents;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw IoError("cannot read the results log " + path + ": " + std::strerror(errno));
  }
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  std::size_t begin = 0;
  int number = 0;
  while (begin < text.size()) {
    ++number;
    const std::size_t end = text.find('\n', begin);
    const bool last = end == std::string::npos || end + 1 == text.size();
    if (end == std::string::npos) {  // no newline: a write cut off
      contents.torn_bytes = text.size() - begin;
      break;
    }
    const std::string line = text.substr(begin, end - begin);
    try {
      contents.records.push_back(parse_mesh_record(line));
    } catch (const InvalidInput& e) {
      if (!last) {
        throw InvalidInput("the results log " + path + " line " + std::to_string(number) + ": " +
                           e.what() + "; move the file away to start the batch afresh");
      }
      contents.torn_bytes = text.size() - begin;
      break;
    }
    begin = end + 1;
  }
  contents.valid_bytes = begin;
  return contents;
}

void rewrite_results_log(const std::string& path, const std::vector<MeshRecord>& records) {
  write_file_atomically(path, [&](std::ostream& out) {
    for (const MeshRecord& r : records) out << to_json_line(r) << "\n";
  });
}

ResultsLogWriter::ResultsLogWriter(const std::string& path) : path_(path) {
  fd_ = ::open(path.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    throw IoError("cannot open the results log " + path +
                  " for appending: " + std::strerror(errno));
  }
}

ResultsLogWriter::~ResultsLogWriter() {
  if (fd_ >= 0) ::close(fd_);
}

void ResultsLogWriter::append(const MeshRecord& record) {
  const std::string line = to_json_line(record) + "\n";
  // One write(2) per line: O_APPEND places it whole at the end; a kill leaves at most a torn
  // last line, which read_results_log ignores.
  std::size_t written = 0;
  while (written < line.size()) {
    const ssize_t n = ::write(fd_, line.data() + written, line.size() - written);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw IoError("writing the results log " + path_ + " failed: " + std::strerror(errno));
    }
    written += static_cast<std::size_t>(n);
  }
  if (::fdatasync(fd_) != 0) {
    throw IoError("syncing the results log " + path_ + " failed: " + std::strerror(errno));
  }
}

std::string hash_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError("cannot read " + path + " to hash it: " + std::strerror(errno));
  std::uint64_t hash = 14695981039346656037ull;
  std::array<char, 1 << 16> buffer;
  while (in) {
    in.read(buffer.data(), buffer.size());
    const std::streamsize n = in.gcount();
    for (std::streamsize i = 0; i < n; ++i) {
      hash ^= static_cast<unsigned char>(buffer[static_cast<std::size_t>(i)]);
      hash *= 1099511628211ull;
    }
  }
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return std::string("fnv1a64:") + text;
}

}  // namespace ricci
