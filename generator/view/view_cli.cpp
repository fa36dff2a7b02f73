#include "view/view_cli.hpp"

#include <CLI/CLI.hpp>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <unistd.h>

#include "core/errors.hpp"
#include "render/render.hpp"
#include "view/view_server.hpp"

namespace fs = std::filesystem;

namespace cs {
namespace {

std::string this_executable() {
    std::error_code ec;
    auto p = fs::read_symlink("/proc/self/exe", ec);
    return ec ? std::string("clever-support") : p.string();
}

}  // namespace

CLI::App* add_view_command(CLI::App& app, ViewArgs& a) {
    auto* cmd = app.add_subcommand("view", "See and edit the supports in a browser: serves a page on 127.0.0.1 and prints\n"
                                           "its address (with a random token); edits go into the .scad's [Manual edits].\n"
                                           "Example: clever-support view out/m/");
    cmd->add_option("folder", a.target, "An output folder, or the .scad clever-support wrote in it")->required();
    return cmd;
}

int run_view_command(const ViewArgs& a) {
    ViewOptions o;
    o.target = a.target;
    o.cli = this_executable();
    o.page_dir = data_dir() + "/view";
    const std::string server = (fs::path(o.cli).parent_path() / kViewServer).string();
    const std::vector<std::string> args = view_server_args(o);
    std::vector<char*> argv;
    for (const std::string& s : args) argv.push_back(const_cast<char*>(s.c_str()));
    argv.push_back(nullptr);
    execv(server.c_str(), argv.data());
    throw ExternalToolError("cannot start the page's server " + server + ": " + std::strerror(errno) +
                            "; it is installed beside clever-support (cmake --install, or the .deb): reinstall");
}

std::vector<std::string> view_server_args(const ViewOptions& o) { return {kViewServer, o.target, o.cli, o.page_dir}; }

std::optional<ViewOptions> view_options_from_args(int argc, const char* const* argv) {
    if (argc != 4) return std::nullopt;
    return ViewOptions{argv[1], argv[2], argv[3]};
}

}  // namespace cs
