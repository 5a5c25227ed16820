#pragma once
// What the records of a run say about the program that made them.

namespace kdem {

// Short commit hash of the source tree at build time, with "-modified" when it had changes
// that were not committed (generated at every build by cmake/git_hash.cmake).
const char* git_hash();

} // namespace kdem
