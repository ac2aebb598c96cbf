// linkfit_atlas FILE: builds the coupler-curve atlas of the default options
// (optimizers/coupler_atlas.h) and writes it to FILE, for the library to read instead of
// building it on first use. Run by the build; exit 1 when it cannot write.
#include <cstdio>
#include <filesystem>
#include <string>

#include "optimizers/coupler_atlas.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: linkfit_atlas FILE\n");
    return 2;
  }
  const std::filesystem::path path(argv[1]);
  std::error_code error;
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path(), error);
  const linkfit::CouplerAtlas atlas;
  // Written beside and renamed: a reader never sees half a file.
  const std::string temporary = path.string() + ".partial";
  if (!atlas.Write(temporary)) {
    std::fprintf(stderr, "linkfit_atlas: %s: cannot write\n", temporary.c_str());
    return 1;
  }
  std::filesystem::rename(temporary, path, error);
  if (error) {
    std::fprintf(stderr, "linkfit_atlas: %s: %s\n", path.c_str(), error.message().c_str());
    return 1;
  }
  std::printf("linkfit_atlas: %zu four-bars, %zu closed and %zu open keys: %s\n",
              atlas.four_bar_count(), atlas.closed_key_count(), atlas.open_key_count(),
              path.c_str());
  return 0;
}
