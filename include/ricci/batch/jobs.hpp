#pragma once
/// \file
/// The meshes of a batch: a folder (every OBJ/OFF/PLY/STL under it), a manifest (one path per
/// line, or path TAB per-mesh options), or a list of paths; each becomes a BatchJob that names its
/// outputs under the batch's output folder.

#include <cstdint>
#include <string>
#include <vector>

namespace ricci {

/// One mesh of a batch and where its results go.
struct BatchJob {
  /// The mesh file as the worker opens it (absolute).
  std::string input;
  /// Its path relative to the batch's root (the input folder, the manifest's folder, or the
  /// common folder of a list of paths), with '/' separators: names the mesh in the results log,
  /// in the summary and in the outputs.
  std::string key;
  /// The UV OBJ: OUTDIR/<name>.obj (.glb when the options ask for `--format glb`), where <name>
  /// is the key without its extension, or with the extension's dot turned into '_' when another
  /// mesh of the batch has the same key without extension (a.off and a.stl: a_off, a_stl).
  std::string output;
  /// The JSON report of `ricci param`: OUTDIR/<name>.json.
  std::string report;
  /// `ricci param` options for this mesh: the batch's own, then the manifest line's.
  std::vector<std::string> options;
  /// Size of the input in bytes: the scheduler starts the largest meshes first.
  std::uintmax_t bytes = 0;
};

/// The mesh formats a folder is scanned for (lower case, with the dot).
const std::vector<std::string>& batch_mesh_extensions();

/// The jobs of INPUT, a folder or a manifest file.
/// - Folder: every file under it (recursively) whose extension is .obj, .off, .ply or .stl (any
///   case), in lexicographic order of key; hidden files and folders, and out_dir when it lies
///   inside, are skipped.
/// - Manifest: one mesh per line; blank lines and lines starting with '#' skipped; a line may add
///   per-mesh options after a TAB (split like a shell: quotes and backslashes). Relative paths
///   are relative to the manifest's folder.
/// \param options `ricci param` options for every mesh (before each line's own)
/// \throw InvalidInput when INPUT does not exist, a manifest line names a missing file or has
///        unbalanced quotes (with file and line), two meshes would still write the same output
///        (naming both: a.off, a.stl and an a_off.obj), an output would overwrite an input, or no
///        mesh is found
std::vector<BatchJob> list_batch_jobs(const std::string& input, const std::string& out_dir,
                                      const std::vector<std::string>& options);

/// The jobs of a list of mesh paths (keys relative to their common folder); what
/// list_batch_jobs does with a manifest's lines, without per-mesh options.
/// \throw InvalidInput as list_batch_jobs
std::vector<BatchJob> batch_jobs_from_paths(const std::vector<std::string>& paths,
                                            const std::string& out_dir,
                                            const std::vector<std::string>& options);

/// Splits a manifest line's options like a POSIX shell does words: blanks separate, single
/// quotes keep everything, double quotes keep all but backslash escapes, a backslash outside
/// quotes escapes the next character.
/// \throw InvalidInput on an unterminated quote or a trailing backslash
std::vector<std::string> split_shell_words(const std::string& text);

}  // namespace ricci
