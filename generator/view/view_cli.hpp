// The `view` subcommand's hook into the command line (cli/command_line.cpp adds it, cli/main.cpp
// runs it): its arguments and its run.
#pragma once

#include <string>

namespace CLI {
class App;
}

namespace cs {

struct ViewArgs {
    std::string target;  // out/m/ or out/m/m.scad
};

// Adds `view` to `app`; the returned subcommand's parsed() tells whether it was chosen.
CLI::App* add_view_command(CLI::App& app, ViewArgs& a);

// Serves the page (view_server.hpp) until stopped. The page's files are found where the render
// stage finds the OpenSCAD runner: data_dir() + "/view" (<bin>/../share/clever-support/view;
// in the build tree a link to generator/view, cmake/install.cmake). Throws what serve_view throws.
int run_view_command(const ViewArgs& a);

}  // namespace cs
