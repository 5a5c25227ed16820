#pragma once
// Atomic file output: every output file is first written under a temporary name in the same
// directory, then renamed over its final name, so a reader never sees a half-written file.
#include <filesystem>
#include <string>

namespace kdem {

// A fresh temporary name in final_path's directory: ".<file name>.tmp.<process id>.<counter>".
// The leading dot hides it from directory listings and from ParaView's file dialog.
std::filesystem::path temporary_path_for(const std::filesystem::path& final_path);

// Renames tmp over final_path (replacing an existing file). On failure, removes tmp and throws
// std::runtime_error naming both files.
void commit_temporary(const std::filesystem::path& tmp, const std::filesystem::path& final_path);

// Writes content to a temporary file beside path and renames it to path. Throws
// std::runtime_error naming path when the file cannot be written; no temporary file remains.
void write_text_atomically(const std::filesystem::path& path, const std::string& content);

// Owns a temporary file for one atomic write: write to temporary(), then commit(). If commit()
// is never called (an exception, an early return), the destructor removes the temporary file.
class PendingFile {
public:
  explicit PendingFile(std::filesystem::path final_path);
  ~PendingFile();
  PendingFile(const PendingFile&) = delete;
  PendingFile& operator=(const PendingFile&) = delete;

  const std::filesystem::path& temporary() const { return temporary_path_; }
  const std::filesystem::path& final_path() const { return final_path_; }
  void commit();  // renames temporary() to final_path(); throws as commit_temporary does
  void discard(); // removes temporary() now; never throws

private:
  std::filesystem::path final_path_;
  std::filesystem::path temporary_path_;
  bool done_ = false;
};

} // namespace kdem
