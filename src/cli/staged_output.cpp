#include "kane_sim/cli/staged_output.h"

#include <filesystem>
#include <iostream>

namespace kane_sim {
namespace cli {

StagedPath::StagedPath(std::string path) : path_(std::move(path)), staging_(path_ + ".partial") {
  std::error_code error;
  if (std::filesystem::is_symlink(path_, error) ||
      (std::filesystem::exists(path_, error) && !std::filesystem::is_regular_file(path_, error))) {
    staging_ = path_;
    published_ = true;
    return;
  }
  // A leftover FILE.partial that is a link (planted in a shared folder, or left by another tool)
  // would be written through: the link goes, the output gets a file of its own.
  if (std::filesystem::is_symlink(staging_, error)) std::filesystem::remove(staging_, error);
}

StagedPath::~StagedPath() {
  std::error_code error;
  if (!published_) std::filesystem::remove(staging_, error);
}

void StagedPath::publish() {
  if (staging_ == path_) return;
  std::error_code error;
  std::filesystem::rename(staging_, path_, error);
  if (error)
    throw OutputError("cannot rename '" + staging_ + "' to '" + path_ + "': " + error.message());
  published_ = true;
}

CsvOutput::CsvOutput(const std::string& path) {
  if (path.empty()) return;
  staged_ = std::make_unique<StagedPath>(path);
  file_.open(staged_->staging());
  if (!file_) throw OutputError("cannot write --csv '" + path + "'");
}

void CsvOutput::flush() {
  stream().flush();
  if (!stream()) throw OutputError("writing the CSV failed (disk full?)");
}

void CsvOutput::finish() {
  flush();
  if (!staged_) return;
  file_.close();
  staged_->publish();
}

}  // namespace cli
}  // namespace kane_sim
