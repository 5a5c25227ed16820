#include "atomic_file.hpp"

#include <atomic>
#include <fstream>
#include <stdexcept>
#include <system_error>

#include <unistd.h>

namespace kdem {

namespace fs = std::filesystem;

namespace {

std::atomic<unsigned long> temporary_file_counter{0};

void remove_quietly(const fs::path& path) noexcept {
  std::error_code ignored;
  fs::remove(path, ignored);
}

} // namespace

fs::path temporary_path_for(const fs::path& final_path) {
  if (final_path.filename().empty()) {
    throw std::runtime_error("cannot write '" + final_path.string() + "': not a file name");
  }
  const std::string unique_suffix = ".tmp." + std::to_string(::getpid()) + "." +
                                    std::to_string(temporary_file_counter.fetch_add(1));
  return final_path.parent_path() / ("." + final_path.filename().string() + unique_suffix);
}

void commit_temporary(const fs::path& tmp, const fs::path& final_path) {
  std::error_code error;
  fs::rename(tmp, final_path, error);
  if (error) {
    remove_quietly(tmp);
    throw std::runtime_error("cannot write '" + final_path.string() + "': renaming '" +
                             tmp.string() + "' failed: " + error.message());
  }
}

void write_text_atomically(const fs::path& path, const std::string& content) {
  PendingFile pending(path);
  {
    std::ofstream stream(pending.temporary(), std::ios::binary | std::ios::trunc);
    if (!stream) {
      throw std::runtime_error("cannot write '" + path.string() +
                               "': cannot create temporary file '" + pending.temporary().string() +
                               "'");
    }
    stream.write(content.data(), static_cast<std::streamsize>(content.size()));
    stream.close();
    if (!stream) {
      throw std::runtime_error("cannot write '" + path.string() + "': writing '" +
                               pending.temporary().string() + "' failed");
    }
  }
  pending.commit();
}

PendingFile::PendingFile(fs::path final_path)
    : final_path_(std::move(final_path)), temporary_path_(temporary_path_for(final_path_)) {}

PendingFile::~PendingFile() {
  discard();
}

void PendingFile::commit() {
  if (done_) {
    throw std::logic_error("file '" + final_path_.string() + "' already committed or discarded");
  }
  done_ = true;
  commit_temporary(temporary_path_, final_path_);
}

void PendingFile::discard() {
  if (!done_) {
    done_ = true;
    remove_quietly(temporary_path_);
  }
}

} // namespace kdem
