#include "ricci/batch/jobs.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>

#include "ricci/errors.hpp"

namespace ricci {
namespace fs = std::filesystem;

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

bool is_mesh_file(const fs::path& path) {
  const std::string extension = lower(path.extension().string());
  const auto& known = batch_mesh_extensions();
  return std::find(known.begin(), known.end(), extension) != known.end();
}

/// Absolute and lexically normal, symbolic links kept (the user's names stay in the log).
fs::path absolute_normal(const fs::path& path) {
  return fs::absolute(path).lexically_normal();
}

/// True when `inner` is `outer` or lies under it (both absolute and normal).
bool lies_under(const fs::path& inner, const fs::path& outer) {
  const fs::path relative = inner.lexically_relative(outer);
  return !relative.empty() && *relative.begin() != "..";
}

/// `--format glb` (or `--format=glb`) among param options: the output is KEY.glb; the last
/// --format given wins, as in param's parser.
bool asks_for_glb(const std::vector<std::string>& options) {
  bool glb = false;
  for (std::size_t i = 0; i < options.size(); ++i) {
    if (options[i] == "--format" && i + 1 < options.size()) glb = options[i + 1] == "glb";
    if (options[i].starts_with("--format=")) glb = options[i] == "--format=glb";
  }
  return glb;
}

struct Entry {
  fs::path input;  // absolute, normal
  std::vector<std::string> options;
  std::string where;  // "manifest line N" or the path, for messages
};

/// Where each entry's outputs go, relative to the output folder and without their extension:
/// its path relative to `root` less the extension, or, where two entries share that (a.off and
/// a.stl), with the extension's dot turned into '_' (a_off, a_stl). An entry whose name is unique
/// keeps the name it always had, so a resumed batch finds its outputs. Depends only on the set
/// of inputs, not on their order.
std::vector<fs::path> output_stems(const std::vector<Entry>& entries, const fs::path& root) {
  std::vector<fs::path> stems;
  stems.reserve(entries.size());
  std::map<fs::path, int> sharing;
  for (const Entry& entry : entries) {
    stems.push_back(entry.input.lexically_relative(root).replace_extension());
    ++sharing[stems.back()];
  }
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const std::string extension = entries[i].input.extension().string();
    if (sharing[stems[i]] > 1 && !extension.empty()) {
      stems[i] += "_" + extension.substr(1);
    }
  }
  return stems;
}

/// Keys relative to root; outputs under out_dir; the checks every source of jobs shares.
std::vector<BatchJob> make_jobs(const std::vector<Entry>& entries, const fs::path& root,
                                const std::string& out_dir,
                                const std::vector<std::string>& options) {
  if (entries.empty()) throw InvalidInput("ricci batch: no mesh to run");
  const fs::path out = absolute_normal(out_dir);
  std::vector<BatchJob> jobs;
  std::map<std::string, std::size_t> by_output;
  std::map<std::string, std::size_t> by_input;
  const std::vector<fs::path> stems = output_stems(entries, root);
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const Entry& entry = entries[i];
    BatchJob job;
    job.input = entry.input.string();
    job.key = entry.input.lexically_relative(root).generic_string();
    const fs::path stem = out / stems[i];
    job.options = options;
    job.options.insert(job.options.end(), entry.options.begin(), entry.options.end());
    job.output = stem.string() + (asks_for_glb(job.options) ? ".glb" : ".obj");
    job.report = stem.string() + ".json";
    std::error_code error;
    const std::uintmax_t bytes = fs::file_size(entry.input, error);
    if (error) {
      throw InvalidInput("ricci batch: " + entry.where + ": cannot read " + job.input + ": " +
                         error.message());
    }
    job.bytes = bytes;
    if (const auto [it, fresh] = by_input.emplace(job.input, jobs.size()); !fresh) {
      throw InvalidInput("ricci batch: " + entry.where + ": " + job.input +
                         " is listed twice (also " + entries[it->second].where + ")");
    }
    if (const auto [it, fresh] = by_output.emplace(job.output, jobs.size()); !fresh) {
      throw InvalidInput("ricci batch: " + jobs[it->second].input + " and " + job.input +
                         " would both write " + job.output +
                         "; rename one, or run them in separate batches");
    }
    jobs.push_back(std::move(job));
  }
  for (const BatchJob& job : jobs) {
    for (const std::string& written : {job.output, job.report}) {
      if (const auto it = by_input.find(written); it != by_input.end()) {
        throw InvalidInput("ricci batch: the output " + written + " of " + job.input +
                           " would overwrite an input; choose an output folder (-o) apart from "
                           "the meshes");
      }
    }
  }
  return jobs;
}

/// The deepest folder holding every path.
fs::path common_folder(const std::vector<Entry>& entries) {
  fs::path common = entries.front().input.parent_path();
  for (const Entry& entry : entries) {
    while (!lies_under(entry.input, common)) {
      if (common == common.root_path()) return common;
      common = common.parent_path();
    }
  }
  return common;
}

std::vector<Entry> read_manifest(const fs::path& manifest) {
  std::ifstream in(manifest);
  if (!in) throw IoError("ricci batch: cannot read the manifest " + manifest.string());
  std::vector<Entry> entries;
  std::string line;
  const fs::path folder = manifest.parent_path();
  for (int number = 1; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string where = manifest.string() + " line " + std::to_string(number);
    const std::size_t tab = line.find('\t');
    std::string path = line.substr(0, tab);
    const std::size_t first = path.find_first_not_of(' ');
    if (first == std::string::npos || path[first] == '#') continue;
    path = path.substr(first, path.find_last_not_of(' ') + 1 - first);
    Entry entry;
    entry.input = absolute_normal(fs::path(path).is_absolute() ? fs::path(path) : folder / path);
    entry.where = where;
    if (tab != std::string::npos) {
      try {
        entry.options = split_shell_words(line.substr(tab + 1));
      } catch (const InvalidInput& e) {
        throw InvalidInput("ricci batch: " + where + ": " + e.what());
      }
    }
    std::error_code error;
    if (!fs::is_regular_file(entry.input, error)) {
      throw InvalidInput("ricci batch: " + where + ": no such mesh file " + entry.input.string());
    }
    entries.push_back(std::move(entry));
  }
  if (entries.empty()) {
    throw InvalidInput("ricci batch: the manifest " + manifest.string() + " lists no mesh");
  }
  return entries;
}

}  // namespace

const std::vector<std::string>& batch_mesh_extensions() {
  static const std::vector<std::string> extensions = {".obj", ".off", ".ply", ".stl"};
  return extensions;
}

std::vector<BatchJob> list_batch_jobs(const std::string& input, const std::string& out_dir,
                                      const std::vector<std::string>& options) {
  std::error_code error;
  const fs::path root = absolute_normal(input);
  const fs::file_status status = fs::status(root, error);
  if (!fs::exists(status)) throw InvalidInput("ricci batch: " + input + ": no such file or folder");
  if (!fs::is_directory(status)) {
    const std::vector<Entry> entries = read_manifest(root);
    const fs::path folder = root.parent_path();
    const bool all_under = std::all_of(entries.begin(), entries.end(),
                                       [&](const Entry& e) { return lies_under(e.input, folder); });
    return make_jobs(entries, all_under ? folder : common_folder(entries), out_dir, options);
  }
  const fs::path out = absolute_normal(out_dir);
  std::vector<Entry> entries;
  for (auto it = fs::recursive_directory_iterator(root, error);
       !error && it != fs::recursive_directory_iterator(); it.increment(error)) {
    const fs::path path = absolute_normal(it->path());
    const bool hidden = path.filename().string().starts_with(".");
    if (it->is_directory(error)) {
      if (hidden || lies_under(path, out)) it.disable_recursion_pending();
      continue;
    }
    if (hidden || !it->is_regular_file(error) || !is_mesh_file(path)) continue;
    entries.push_back({path, {}, path.string()});
  }
  if (error) throw IoError("ricci batch: cannot list " + input + ": " + error.message());
  if (entries.empty()) {
    throw InvalidInput("ricci batch: no .obj, .off, .ply or .stl file under " + input);
  }
  std::sort(entries.begin(), entries.end(),
            [](const Entry& a, const Entry& b) { return a.input < b.input; });
  return make_jobs(entries, root, out_dir, options);
}

std::vector<BatchJob> batch_jobs_from_paths(const std::vector<std::string>& paths,
                                            const std::string& out_dir,
                                            const std::vector<std::string>& options) {
  std::vector<Entry> entries;
  for (std::size_t i = 0; i < paths.size(); ++i) {
    Entry entry{absolute_normal(paths[i]), {}, "path " + std::to_string(i) + " (" + paths[i] + ")"};
    std::error_code error;
    if (!fs::is_regular_file(entry.input, error)) {
      throw InvalidInput("ricci batch: " + entry.where + ": no such mesh file");
    }
    entries.push_back(std::move(entry));
  }
  if (entries.empty()) throw InvalidInput("ricci batch: no mesh to run");
  return make_jobs(entries, common_folder(entries), out_dir, options);
}

std::vector<std::string> split_shell_words(const std::string& text) {
  std::vector<std::string> words;
  std::string word;
  bool in_word = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == ' ' || c == '\t' || c == '\n') {
      if (in_word) words.push_back(word);
      word.clear();
      in_word = false;
      continue;
    }
    in_word = true;
    if (c == '\'') {
      const std::size_t end = text.find('\'', i + 1);
      if (end == std::string::npos) throw InvalidInput("unterminated single quote in: " + text);
      word += text.substr(i + 1, end - i - 1);
      i = end;
    } else if (c == '"') {
      std::size_t j = i + 1;
      for (; j < text.size() && text[j] != '"'; ++j) {
        if (text[j] == '\\' && j + 1 < text.size() &&
            std::string("\"\\$`").find(text[j + 1]) != std::string::npos) {
          ++j;
        }
        word += text[j];
      }
      if (j >= text.size()) throw InvalidInput("unterminated double quote in: " + text);
      i = j;
    } else if (c == '\\') {
      if (i + 1 >= text.size()) throw InvalidInput("trailing backslash in: " + text);
      word += text[++i];
    } else {
      word += c;
    }
  }
  if (in_word) words.push_back(word);
  return words;
}

}  // namespace ricci
