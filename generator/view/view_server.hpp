// `clever-support view`: a local web page to see and edit one output folder's supports.
//
// Safety: it listens on 127.0.0.1 only, on a free port the system picks, and every request must
// carry a random token as its first path segment (http://127.0.0.1:PORT/TOKEN/) and a Host header
// naming that address; anything else is refused (403). It serves a fixed set of files only:
// the page, the pinned three.js (generator/view/node_modules), and the folder's <name>.model.stl,
// <name>.supports.stl and <name>.report.json, each under a fixed name; no part of a request's path
// becomes a file name. It writes one file: the folder's <name>.scad.
//
// Regrow runs `clever-support regrow <name>.scad -v` (this very executable), so it is the same
// code, with the same messages, and its progress lines are passed to the page.
#pragma once

#include <string>

namespace cs {

struct ViewOptions {
    std::string target;    // an output folder or its .scad (find_view_folder)
    std::string cli;       // the clever-support executable, for regrow
    std::string page_dir;  // holding page/ and node_modules/three/
};

// Serves until the process is stopped (Ctrl+C). Prints the page's address on stdout and opens
// nothing. Throws InputError for a target that is not an output folder, ExternalToolError when
// the page's files (three.js) are not installed, OutputError when no port can be bound.
void serve_view(const ViewOptions& o);

// Whether a request may be answered: Host is "127.0.0.1:PORT" or "localhost:PORT", and the path
// starts with "/TOKEN/". Example: view_request_allowed("127.0.0.1:8080", "/ab12/", "ab12", 8080).
bool view_request_allowed(const std::string& host, const std::string& path, const std::string& token, int port);

}  // namespace cs
