#pragma once
// temporary output files known to a signal handler: a run stopped by SIGINT, SIGTERM,
// SIGHUP or SIGQUIT removes them before it dies, so no *.tmp-XXXXXX file outlives it.
#include <string>

namespace camopt::io::detail {

// create `path` + ".tmp-XXXXXX" (mkstemp) and register it for removal on a signal; the
// handlers are installed on the first call (a signal the process ignores stays ignored).
// Returns the open descriptor (or -1 with errno set) and the temp path in `temp_path`.
int create_registered_temp(const std::string& path, std::string& temp_path);

// the temp file is gone (renamed or unlinked): the handler no longer removes it
void forget_temp(const std::string& temp_path);

}  // namespace camopt::io::detail
