// The `view` subcommand's hook into the command line (cli/command_line.cpp adds it, cli/main.cpp
// runs it): its arguments and its run.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "view/view_server.hpp"

namespace CLI {
class App;
}

namespace cs {

struct ViewArgs {
    std::string target;  // out/m/ or out/m/m.scad
};

// Adds `view` to `app`; the returned subcommand's parsed() tells whether it was chosen.
CLI::App* add_view_command(CLI::App& app, ViewArgs& a);

// Serves the page (view_server.hpp) until stopped, in the server's own executable (kViewServer,
// beside this one), which this process becomes (execv): the web server and the libraries it
// brings (cpp-httplib, libssl, brotli) are loaded only by `view`, not by every run (`--version`
// 9.7 -> 7.0 ms of CPU). The page's files are found where the render stage finds the
// OpenSCAD runner: data_dir() + "/view" (<bin>/../share/clever-support/view; in the build tree a
// link to generator/view, cmake/install.cmake). Throws ExternalToolError when the server cannot
// be started; the server throws what serve_view throws.
int run_view_command(const ViewArgs& a);

// The server's executable, installed beside clever-support (cli/view_main.cpp).
inline constexpr const char* kViewServer = "clever-support-view";

// The server's command line for `o`, and `o` back from it (none: not such a command line).
// Example: view_options_from_args(4, {"clever-support-view", "out/m/", "/usr/bin/clever-support",
// "/usr/share/clever-support/view"}).
std::vector<std::string> view_server_args(const ViewOptions& o);
std::optional<ViewOptions> view_options_from_args(int argc, const char* const* argv);

}  // namespace cs
