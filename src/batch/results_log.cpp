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
#include <string_view>
#include <type_traits>

#include "batch/detail/json_numbers.hpp"
#include "ricci/errors.hpp"
#include "ricci/mesh/io.hpp"

namespace ricci {

namespace {

using batch_detail::number_or_null;

double number_or_nan(const nlohmann::json& j, const char* name) {
  const auto it = j.find(name);
  if (it == j.end() || !it->is_number()) return std::numeric_limits<double>::quiet_NaN();
  return it->get<double>();
}

/// A figure that a record stores as NaN when unknown and JSON as null (or leaves out).
template <class Number>
struct NumberOrNull {
  Number& value;
};

/// Calls visit(name, field) on each field of a record (a MeshRecord, const or not) under its
/// JSON name, in the order of MeshRecord: the writer and the reader of a record share this one
/// list. The distortions come wrapped in NumberOrNull.
template <class Record, class Visit>
void for_each_field(Record& r, Visit&& visit) {
  using Number = std::remove_reference_t<decltype((r.area_distortion))>;
  visit("key", r.key);
  visit("input", r.input);
  visit("input_hash", r.input_hash);
  visit("input_stamp", r.input_stamp);
  visit("options", r.options);
  visit("outcome", r.outcome);
  visit("exit_code", r.exit_code);
  visit("signal", r.signal);
  visit("seconds", r.seconds);
  visit("peak_memory_kb", r.peak_memory_kb);
  visit("message", r.message);
  visit("output", r.output);
  visit("report", r.report);
  visit("area_distortion", NumberOrNull<Number>{r.area_distortion});
  visit("angle_distortion", NumberOrNull<Number>{r.angle_distortion});
  visit("flipped_faces", r.flipped_faces);
  visit("cones", r.cones);
  visit("worker", r.worker);
  visit("finished_at", r.finished_at);
  visit("version", r.version);
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
  for_each_field(r, [&](const char* name, const auto& field) {
    using Field = std::decay_t<decltype(field)>;
    if constexpr (std::is_same_v<Field, MeshOutcome>) {
      j[name] = mesh_outcome_name(field);
    } else if constexpr (std::is_same_v<Field, NumberOrNull<const double>>) {
      j[name] = number_or_null(field.value);
    } else {
      j[name] = field;
    }
  });
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
    for_each_field(r, [&](const char* name, auto&& field) {
      using Field = std::decay_t<decltype(field)>;
      if constexpr (std::is_same_v<Field, MeshOutcome>) {
        field = parse_mesh_outcome(j.at(name).get<std::string>());
      } else if constexpr (std::is_same_v<Field, NumberOrNull<double>>) {
        field.value = number_or_nan(j, name);
      } else if (std::string_view(name) == "key") {
        field = j.at(name).get<Field>();  // required: a record names its mesh
      } else {
        field = j.value(name, field);  // absent: the default of a MeshRecord
      }
    });
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
