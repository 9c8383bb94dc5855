// The meshes of a batch: folders, manifests, lists; keys, outputs and the refusals.
#include "ricci/batch/jobs.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "ricci/errors.hpp"
#include "support/shared_meshes.hpp"

namespace ricci {
namespace {

namespace fs = std::filesystem;

/// A fresh folder for one test.
fs::path test_temp_dir(const std::string& name) {
  return testing::fresh_tmp_dir(name);
}

void touch(const fs::path& path, const std::string& text = "v 0 0 0\n") {
  testing::write_text_file(path, text);
}

std::vector<std::string> keys(const std::vector<BatchJob>& jobs) {
  std::vector<std::string> k;
  k.reserve(jobs.size());
  for (const BatchJob& j : jobs) k.push_back(j.key);
  return k;
}

TEST(BatchJobs, AFolderGivesEveryMeshUnderItInKeyOrder) {
  const fs::path root = test_temp_dir("batch_jobs_folder");
  touch(root / "in/b.OBJ");
  touch(root / "in/a.ply", "ply\n and more bytes");
  touch(root / "in/sub/c.stl");
  touch(root / "in/sub/readme.txt");
  touch(root / "in/.hidden/d.obj");
  touch(root / "in/.e.obj");
  touch(root / "in/out/old.obj");  // the output folder inside the input folder is skipped
  const std::vector<BatchJob> jobs =
      list_batch_jobs((root / "in").string(), (root / "in/out").string(), {"--cones", "8"});
  EXPECT_EQ(keys(jobs), (std::vector<std::string>{"a.ply", "b.OBJ", "sub/c.stl"}));
  EXPECT_EQ(jobs[0].output, (root / "in/out/a.obj").string());
  EXPECT_EQ(jobs[0].report, (root / "in/out/a.json").string());
  EXPECT_EQ(jobs[2].output, (root / "in/out/sub/c.obj").string());
  EXPECT_EQ(jobs[0].bytes, 19u);
  EXPECT_EQ(jobs[1].options, (std::vector<std::string>{"--cones", "8"}));
  EXPECT_TRUE(fs::path(jobs[1].input).is_absolute());
}

TEST(BatchJobs, AManifestGivesPerMeshOptionsAfterTheBatchsOwn) {
  const fs::path root = test_temp_dir("batch_jobs_manifest");
  touch(root / "m/a.obj");
  touch(root / "m/sub/b.off");
  std::ofstream(root / "m/list.tsv") << "# meshes\n\na.obj\nsub/b.off\t--cones 'one' --tol=1e-9\n";
  const std::vector<BatchJob> jobs =
      list_batch_jobs((root / "m/list.tsv").string(), (root / "o").string(), {"--repair"});
  ASSERT_EQ(keys(jobs), (std::vector<std::string>{"a.obj", "sub/b.off"}));
  EXPECT_EQ(jobs[0].options, (std::vector<std::string>{"--repair"}));
  EXPECT_EQ(jobs[1].options,
            (std::vector<std::string>{"--repair", "--cones", "one", "--tol=1e-9"}));
  EXPECT_EQ(jobs[1].output, (root / "o/sub/b.obj").string());
  // --format glb, for every mesh or on one line: that mesh's output is KEY.glb.
  std::ofstream(root / "m/glb.tsv") << "a.obj\t--format glb\nsub/b.off\n";
  const std::vector<BatchJob> glb =
      list_batch_jobs((root / "m/glb.tsv").string(), (root / "o").string(), {});
  EXPECT_EQ(glb[0].output, (root / "o/a.glb").string());
  EXPECT_EQ(glb[1].output, (root / "o/sub/b.obj").string());
  EXPECT_EQ(
      list_batch_jobs((root / "m/glb.tsv").string(), (root / "o").string(), {"--format=glb"})[1]
          .output,
      (root / "o/sub/b.glb").string());
}

TEST(BatchJobs, KeysThatDifferOnlyInTheExtensionWriteDistinctOutputs) {
  const fs::path root = test_temp_dir("batch_jobs_shared_stems");
  touch(root / "in/pig.off");
  touch(root / "in/pig.stl");
  touch(root / "in/cow.ply");
  touch(root / "in/sub/pig.obj");  // another output folder: keeps its name
  const std::vector<BatchJob> jobs =
      list_batch_jobs((root / "in").string(), (root / "o").string(), {});
  ASSERT_EQ(keys(jobs), (std::vector<std::string>{"cow.ply", "pig.off", "pig.stl", "sub/pig.obj"}));
  EXPECT_EQ(jobs[0].output, (root / "o/cow.obj").string());  // unique: today's name
  EXPECT_EQ(jobs[1].output, (root / "o/pig_off.obj").string());
  EXPECT_EQ(jobs[1].report, (root / "o/pig_off.json").string());
  EXPECT_EQ(jobs[2].output, (root / "o/pig_stl.obj").string());
  EXPECT_EQ(jobs[2].report, (root / "o/pig_stl.json").string());
  EXPECT_EQ(jobs[3].output, (root / "o/sub/pig.obj").string());

  // A manifest: the names do not depend on the order of its lines, and --format glb on one line
  // changes only that mesh's extension.
  std::ofstream(root / "in/forward.tsv") << "pig.off\npig.stl\t--format glb\ncow.ply\n";
  std::ofstream(root / "in/backward.tsv") << "cow.ply\npig.stl\t--format glb\npig.off\n";
  for (const char* manifest : {"forward.tsv", "backward.tsv"}) {
    SCOPED_TRACE(manifest);
    for (const BatchJob& job :
         list_batch_jobs((root / "in" / manifest).string(), (root / "o").string(), {})) {
      const std::string expected = job.key == "pig.off"   ? "pig_off.obj"
                                   : job.key == "pig.stl" ? "pig_stl.glb"
                                                          : "cow.obj";
      EXPECT_EQ(job.output, (root / "o" / expected).string()) << job.key;
    }
  }
}

TEST(BatchJobs, RefusalsNameTheProblem) {
  const fs::path root = test_temp_dir("batch_jobs_refusals");
  // a.off and a.ply write a_off.obj and a_ply.obj, one of which a_off.obj writes too.
  touch(root / "x/a.off");
  touch(root / "x/a.ply");
  touch(root / "x/a_off.obj");
  try {
    list_batch_jobs((root / "x").string(), (root / "o").string(), {});
    FAIL() << "two meshes writing one output";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("would both write"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("a_off.obj"), std::string::npos) << e.what();
  }
  // Outputs into the input folder would overwrite a.obj.
  touch(root / "y/a.obj");
  EXPECT_THROW(list_batch_jobs((root / "y").string(), (root / "y").string(), {}), InvalidInput);
  std::ofstream(root / "bad.tsv") << "y/a.obj\n"
                                  << "missing.obj\n";
  try {
    list_batch_jobs((root / "bad.tsv").string(), (root / "o").string(), {});
    FAIL() << "a missing mesh";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("bad.tsv line 2"), std::string::npos) << e.what();
  }
  std::ofstream(root / "quote.tsv") << "y/a.obj\t--cones 'one\n";
  EXPECT_THROW(list_batch_jobs((root / "quote.tsv").string(), (root / "o").string(), {}),
               InvalidInput);
  fs::create_directories(root / "empty");
  EXPECT_THROW(list_batch_jobs((root / "empty").string(), (root / "o").string(), {}), InvalidInput);
  EXPECT_THROW(list_batch_jobs((root / "nowhere").string(), (root / "o").string(), {}),
               InvalidInput);
}

TEST(BatchJobs, AListOfPathsIsKeyedFromItsCommonFolder) {
  const fs::path root = test_temp_dir("batch_jobs_paths");
  touch(root / "p/one/a.obj");
  touch(root / "p/two/b.obj");
  const std::vector<BatchJob> jobs =
      batch_jobs_from_paths({(root / "p/one/a.obj").string(), (root / "p/two/b.obj").string()},
                            (root / "o").string(), {});
  EXPECT_EQ(keys(jobs), (std::vector<std::string>{"one/a.obj", "two/b.obj"}));
  EXPECT_THROW(
      batch_jobs_from_paths({(root / "p/one/a.obj").string(), (root / "p/one/a.obj").string()},
                            (root / "o").string(), {}),
      InvalidInput);
}

TEST(BatchJobs, ShellWordsSplitLikeAShell) {
  EXPECT_EQ(split_shell_words("  --cones 8\t--tol=1e-9 "),
            (std::vector<std::string>{"--cones", "8", "--tol=1e-9"}));
  EXPECT_EQ(split_shell_words(R"(--cones 'a b' "c \"d\"" e\ f '')"),
            (std::vector<std::string>{"--cones", "a b", "c \"d\"", "e f", ""}));
  EXPECT_THROW(split_shell_words("'open"), InvalidInput);
  EXPECT_THROW(split_shell_words("\"open"), InvalidInput);
  EXPECT_THROW(split_shell_words("end\\"), InvalidInput);
}

}  // namespace
}  // namespace ricci
