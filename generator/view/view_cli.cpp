#include "view/view_cli.hpp"

#include <CLI/CLI.hpp>
#include <cstdlib>
#include <filesystem>

#include "view/view_server.hpp"

namespace fs = std::filesystem;

namespace cs {
namespace {

std::string this_executable() {
    std::error_code ec;
    auto p = fs::read_symlink("/proc/self/exe", ec);
    return ec ? std::string("clever-support") : p.string();
}

std::string page_dir(const std::string& exe) {
    if (const char* env = std::getenv("CS_VIEW_DIR"); env && *env) return env;
    auto installed = fs::path(exe).parent_path().parent_path() / "share/clever-support/view";
    std::error_code ec;
    if (fs::is_regular_file(installed / "page/index.html", ec)) return installed.string();
    return CS_VIEW_SOURCE_DIR;
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
    o.page_dir = page_dir(o.cli);
    serve_view(o);
    return 0;
}

}  // namespace cs
