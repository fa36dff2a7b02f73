#include "view/view_cli.hpp"

#include <CLI/CLI.hpp>
#include <filesystem>

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
    serve_view(o);
    return 0;
}

}  // namespace cs
