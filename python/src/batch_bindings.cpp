/// \file
/// Bindings of `ricci batch` (ricci/batch/batch.hpp): `_ricci._batch` runs run_batch without the
/// GIL and returns the records as JSON lines and the summary as JSON (the package `ricci` turns
/// them into dicts, python/ricci/_batch.py); `_ricci._check_param_options` checks options meant
/// for `ricci param` with param's own parser (apps/ricci/param_options.cpp, compiled in).

#include <exception>
#include <optional>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "param_command.hpp"
#include "ricci/batch/batch.hpp"
#include "ricci/errors.hpp"

namespace ricci::python {

namespace {

void check_param_options(const std::vector<std::string>& options, const std::string& where) {
  cli::check_param_options(options, where, "out_dir");
}

/// Thrown out of the progress callback to end run_batch after the Python callable raised; the
/// Python exception itself waits in BatchCall::error until the GIL is held again.
struct ProgressRaised : std::exception {
  const char* what() const noexcept override { return "the progress callable raised"; }
};

/// The state of one `_batch` call shared with its progress callback (the scheduler's thread,
/// which is the calling thread).
struct BatchCall {
  py::object callable;              // None: only Ctrl-C is checked
  std::optional<py::object> loads;  // json.loads
  std::exception_ptr error;         // what the callable (or a signal) raised

  void operator()(const BatchProgress& p) {
    py::gil_scoped_acquire gil;
    try {
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
      if (callable.is_none()) return;
      py::dict d;
      d["total"] = p.total;
      d["done"] = p.done;
      d["skipped"] = p.skipped;
      d["ok"] = p.ok;
      d["failed"] = p.failed;
      d["running"] = p.running;
      d["elapsed_seconds"] = p.elapsed_seconds;
      d["meshes_per_minute"] = p.meshes_per_minute;
      d["eta_seconds"] = p.eta_seconds >= 0 ? py::object(py::float_(p.eta_seconds)) : py::none();
      d["last_key"] = p.last != nullptr ? py::object(py::str(p.last->key)) : py::none();
      d["last"] = p.last != nullptr ? (*loads)(py::str(to_json_line(*p.last))) : py::none();
      callable(d);
    } catch (py::error_already_set&) {
      error = std::current_exception();
      throw ProgressRaised();
    }
  }
};

py::tuple batch(const py::object& paths, const std::string& out_dir,
                const std::vector<std::string>& options, const std::string& program, int jobs,
                double timeout, double memory_limit, int threads, bool retry_failed,
                const py::object& progress) {
  if (!progress.is_none() && !PyCallable_Check(progress.ptr())) {
    throw py::type_error("progress must be a callable taking a dict, or None");
  }
  check_param_options(options, "ricci.batch");
  std::vector<BatchJob> batch_jobs;
  if (py::isinstance<py::str>(paths)) {
    batch_jobs = list_batch_jobs(paths.cast<std::string>(), out_dir, options);
  } else {
    batch_jobs = batch_jobs_from_paths(paths.cast<std::vector<std::string>>(), out_dir, options);
  }
  for (const BatchJob& job : batch_jobs) {
    if (job.options.size() > options.size()) {
      check_param_options(job.options, job.key + " (manifest options)");
    }
  }

  BatchOptions batch_options;
  batch_options.program = program;
  batch_options.jobs = jobs;
  batch_options.limits.timeout_seconds = timeout;
  batch_options.limits.memory_limit_mb = memory_limit;
  batch_options.threads_per_job = threads;
  batch_options.retry_failed = retry_failed;
  // Held by the call, not copied into the options: LocalWorkers copies the options on a thread
  // that does not hold the GIL, and a py::object must not be copied there.
  BatchCall call{progress, py::module_::import("json").attr("loads"), nullptr};
  batch_options.progress = [&call](const BatchProgress& p) { call(p); };

  BatchResult result;
  try {
    py::gil_scoped_release no_gil;
    result = run_batch(batch_jobs, out_dir, batch_options);
  } catch (const ProgressRaised&) {
    // The GIL is held again here: raise the callable's exception as it was.
    std::rethrow_exception(call.error);
  }
  py::list lines;
  for (const MeshRecord& record : result.records) lines.append(py::str(to_json_line(record)));
  return py::make_tuple(lines, py::str(summary_to_json(result.summary)));
}

}  // namespace

void bind_batch(py::module_& m) {
  m.def("_batch", &batch, py::arg("paths"), py::arg("out_dir"), py::arg("options"),
        py::arg("program"), py::arg("jobs"), py::arg("timeout"), py::arg("memory_limit"),
        py::arg("threads"), py::arg("retry_failed"), py::arg("progress"),
        "run_batch over `paths` (a str: a folder or a manifest, list_batch_jobs; a list of str: "
        "mesh files, batch_jobs_from_paths), each mesh by `program param MESH -o OBJ --report "
        "JSON options...` in a child process; the GIL is released while it runs. progress: None "
        "or a callable taking a dict (total, done, skipped, ok, failed, running, "
        "elapsed_seconds, meshes_per_minute, eta_seconds, last_key, last), called after each "
        "mesh and once at the start; an exception it raises ends the batch once the running "
        "meshes finish, and is raised. Returns (records as JSON lines, in job order; summary "
        "JSON). Use ricci.batch.");
  m.def("_check_param_options", &check_param_options, py::arg("options"), py::arg("where"),
        "Raises InvalidInput unless every option is one `ricci param` parses and none is one "
        "that ricci batch sets itself.");
#ifdef RICCI_CLI_PATH
  m.attr("_default_program") = RICCI_CLI_PATH;
#else
  m.attr("_default_program") = py::none();
#endif
#ifdef RICCI_INSTALLED_CLI_PATH
  m.attr("_installed_program") = RICCI_INSTALLED_CLI_PATH;
#else
  m.attr("_installed_program") = py::none();
#endif
#ifdef RICCI_CLI_FROM_PACKAGE
  m.attr("_program_from_package") = RICCI_CLI_FROM_PACKAGE;
#else
  m.attr("_program_from_package") = py::none();
#endif
}

}  // namespace ricci::python
