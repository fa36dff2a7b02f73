#include "cli/run_files.hpp"

#include <algorithm>
#include <filesystem>
#include <vector>

#include "core/errors.hpp"
#include "job/job.hpp"

namespace cs {

std::string stem_of(const std::string& path) { return std::filesystem::path(path).stem().string(); }

std::string run_scad(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!fs::is_directory(path, ec)) {
        if (!is_scad_input(path))
            throw UsageError("check " + path + ": give a run's output folder or its .scad (e.g. check out/m/ or check "
                             "out/m/m.scad), or --model and --supports");
        return path;
    }
    std::vector<std::string> found;
    for (const auto& e : fs::directory_iterator(path, ec))
        if (e.path().extension() == ".scad" && e.path().filename() != "clever_support.scad") found.push_back(e.path().string());
    std::sort(found.begin(), found.end());
    if (found.size() == 1) return found[0];
    if (found.empty())
        throw UsageError("check " + path + ": no generated .scad in this folder; give the folder a run wrote (out/<name>/)");
    std::string list;
    for (const auto& f : found) list += " " + f;
    throw UsageError("check " + path + ": several .scad files here; give one of them:" + list);
}

}  // namespace cs
