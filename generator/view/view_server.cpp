#include "view/view_server.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <httplib.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <random>
#include <thread>

#include "core/errors.hpp"
#include "edit/edited_scad.hpp"
#include "mesh/mesh_io.hpp"
#include "view/view_edit.hpp"
#include "view/view_state.hpp"

namespace fs = std::filesystem;

namespace cs {
namespace {

std::string read_all(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path + ": cannot read it");
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::string random_token() {
    std::random_device rd;  // the kernel's randomness
    std::string t;
    for (int i = 0; i < 4; ++i) {
        char buf[9];
        std::snprintf(buf, sizeof buf, "%08x", rd());
        t += buf;
    }
    return t;
}

// Types cpp-httplib does not compress: it compresses "text/..." and a bare "application/json" with
// brotli at its highest quality whenever the browser accepts it, which took 12 s for three.js here.
// Local, nothing to save on the wire.
const char* const kScript = "application/javascript; charset=utf-8";
const char* const kJson = "application/json; charset=utf-8";

// The only files the page may fetch, by the name it asks for: no request path reaches the file
// system. `what` is the served name, the value the file and its content type.
struct Served {
    std::string file, type;
};
std::map<std::string, Served> served_files(const ViewFolder& f, const std::string& page_dir) {
    const std::string three = page_dir + "/node_modules/three/";
    return {
        {"", {page_dir + "/page/index.html", "text/html; charset=utf-8"}},
        {"page/view.js", {page_dir + "/page/view.js", kScript}},
        {"page/view.css", {page_dir + "/page/view.css", "text/css"}},
        {"three/three.module.js", {three + "build/three.module.js", kScript}},
        {"three/three.core.js", {three + "build/three.core.js", kScript}},
        {"three/OrbitControls.js", {three + "examples/jsm/controls/OrbitControls.js", kScript}},
        {"three/STLLoader.js", {three + "examples/jsm/loaders/STLLoader.js", kScript}},
        {"files/model.stl", {f.file(".model.stl"), "application/octet-stream"}},
        {"files/supports.stl", {f.file(".supports.stl"), "application/octet-stream"}},
        {"files/report.json", {f.file(".report.json"), kJson}},
    };
}

// `clever-support regrow FILE -v` in a child process; its output, line by line, for the page.
class Regrow {
public:
    bool start(const std::string& cli, const std::string& scad) {
        std::lock_guard<std::mutex> lock(m_);
        if (running_) return false;
        int fds[2];
        if (pipe(fds) != 0) throw OutputError("cannot start regrow: no pipe");
        pid_t pid = fork();
        if (pid < 0) throw OutputError("cannot start regrow: fork failed");
        if (pid == 0) {
            dup2(fds[1], 1);
            dup2(fds[1], 2);
            for (int fd = 3; fd < 1024; ++fd) close(fd);  // not the server's sockets
            execl(cli.c_str(), cli.c_str(), "regrow", scad.c_str(), "-v", static_cast<char*>(nullptr));
            _exit(127);
        }
        close(fds[1]);
        running_ = true;
        lines_.clear();
        exit_code_ = -1;
        ++runs_;
        if (reader_.joinable()) reader_.join();
        reader_ = std::thread([this, pid, fd = fds[0]] { follow(pid, fd); });
        return true;
    }
    bool running() {
        std::lock_guard<std::mutex> lock(m_);
        return running_;
    }
    nlohmann::json status() {
        std::lock_guard<std::mutex> lock(m_);
        return {{"running", running_}, {"exit", exit_code_}, {"lines", lines_}, {"runs", runs_}};
    }
    ~Regrow() {
        if (reader_.joinable()) reader_.join();
    }

private:
    void follow(pid_t pid, int fd) {
        std::string part;
        char buf[4096];
        for (ssize_t n; (n = read(fd, buf, sizeof buf)) > 0;) {
            part.append(buf, static_cast<size_t>(n));
            for (size_t nl; (nl = part.find_first_of("\r\n")) != std::string::npos; part.erase(0, nl + 1))
                if (nl > 0) add_line(part.substr(0, nl));
        }
        if (!part.empty()) add_line(part);
        close(fd);
        int st = 0;
        waitpid(pid, &st, 0);
        std::lock_guard<std::mutex> lock(m_);
        exit_code_ = WIFEXITED(st) ? WEXITSTATUS(st) : 128;
        running_ = false;
    }
    void add_line(const std::string& l) {
        std::lock_guard<std::mutex> lock(m_);
        lines_.push_back(l);
    }
    std::mutex m_;
    std::thread reader_;
    bool running_ = false;
    int exit_code_ = -1, runs_ = 0;
    std::vector<std::string> lines_;
};

// check's verdict on the written supports, computed again only when they or the .scad change.
class CheckCache {
public:
    nlohmann::json get(const ViewFolder& f, const std::string& scad_text) {
        std::error_code ec;
        auto key = std::to_string(fs::last_write_time(f.file(".supports.stl"), ec).time_since_epoch().count()) + "|" +
                   std::to_string(std::hash<std::string>{}(scad_text));
        std::lock_guard<std::mutex> lock(m_);
        if (key != key_) {
            try {
                value_ = view_check(f, scad_text);
            } catch (const std::exception& e) {
                value_ = {{"error", e.what()}};
            }
            key_ = key;
        }
        return value_;
    }

private:
    std::mutex m_;
    std::string key_;
    nlohmann::json value_;
};

nlohmann::json folder_state(const ViewFolder& f, CheckCache& checks) {
    nlohmann::json s;
    s["name"] = f.name;
    s["scad"] = f.scad();
    try {
        std::string text = read_all(f.scad());
        s.update(view_scad_state(text, f.scad()));
        s["check"] = checks.get(f, text);
    } catch (const std::exception& e) {
        s["error"] = e.what();
    }
    try {
        s["report"] = nlohmann::json::parse(read_all(f.file(".report.json")));
    } catch (const std::exception&) {
        s["report"] = nullptr;
    }
    return s;
}

void send_json(httplib::Response& res, const nlohmann::json& j, int status = 200) {
    res.status = status;
    res.set_content(j.dump(), kJson);
}

}  // namespace

bool view_request_allowed(const std::string& host, const std::string& path, const std::string& token, int port) {
    // Strings built in steps: GCC 12 warns falsely (-Wrestrict) on "literal" + std::string.
    const std::string p = std::to_string(port);
    if (host != std::string("127.0.0.1:").append(p) && host != std::string("localhost:").append(p)) return false;
    std::string prefix(1, '/');
    prefix.append(token).push_back('/');
    if (token.empty() || path.size() < prefix.size()) return false;
    unsigned diff = 0;  // the same time for every wrong token
    for (size_t i = 0; i < prefix.size(); ++i) diff |= static_cast<unsigned char>(path[i] ^ prefix[i]);
    return diff == 0;
}

void serve_view(const ViewOptions& o) {
    const ViewFolder f = find_view_folder(o.target);
    read_edited_scad(f.scad());  // a file regrow cannot read: its message (FILE:LINE) before serving
    const auto files = served_files(f, o.page_dir);
    for (const auto& [name, s] : files)
        if (name.rfind("files/", 0) != 0 && !fs::is_regular_file(s.file))
            throw ExternalToolError("the page of clever-support view is not installed: " + s.file +
                                    " is missing. Run scripts/install-deps.sh (it runs npm ci in generator/view).");
    const std::string token = random_token();
    httplib::Server svr;
    Regrow regrow;
    CheckCache checks;
    std::mutex scad_write;
    int port = svr.bind_to_any_port("127.0.0.1");
    if (port <= 0) throw OutputError("clever-support view: cannot listen on 127.0.0.1 (no free port)");

    svr.set_pre_routing_handler([&](const httplib::Request& req, httplib::Response& res) {
        res.set_header("Cache-Control", "no-store");
        res.set_header("Referrer-Policy", "no-referrer");
        res.set_header("X-Content-Type-Options", "nosniff");
        if (view_request_allowed(req.get_header_value("Host"), req.path, token, port))
            return httplib::Server::HandlerResponse::Unhandled;
        res.status = 403;
        res.set_content("refused: not this page's address\n", "text/plain");
        return httplib::Server::HandlerResponse::Handled;
    });
    const size_t skip = token.size() + 2;  // "/TOKEN/"
    svr.Get(".*", [&](const httplib::Request& req, httplib::Response& res) {
        const std::string what = req.path.substr(skip);
        if (what == "api/state") return send_json(res, folder_state(f, checks));
        if (what == "api/regrow") return send_json(res, regrow.status());
        auto it = files.find(what);
        if (it == files.end()) {
            res.status = 404;
            return res.set_content("not served\n", "text/plain");
        }
        try {
            res.set_content(read_all(it->second.file), it->second.type.c_str());
        } catch (const std::exception& e) {
            res.status = 404;
            res.set_content(std::string(e.what()) + "\n", "text/plain");
        }
    });
    svr.Post(".*", [&](const httplib::Request& req, httplib::Response& res) {
        const std::string what = req.path.substr(skip);
        if (what == "api/regrow") {
            if (!regrow.start(o.cli, f.scad())) return send_json(res, {{"error", "a regrow is running"}}, 409);
            return send_json(res, regrow.status(), 202);
        }
        if (what != "api/edit") return send_json(res, {{"error", "no such action"}}, 404);
        if (regrow.running()) return send_json(res, {{"error", "a regrow is running; edit when it is done"}}, 409);
        try {
            std::lock_guard<std::mutex> lock(scad_write);
            auto edit = nlohmann::json::parse(req.body);
            std::string text = apply_view_edit(read_all(f.scad()), edit, f.scad());
            write_file_atomic(f.scad(), text);
        } catch (const nlohmann::json::exception&) {
            return send_json(res, {{"error", "the edit is not JSON"}}, 400);
        } catch (const std::exception& e) {
            return send_json(res, {{"error", e.what()}}, 400);
        }
        send_json(res, folder_state(f, checks));
    });
    std::printf("clever-support view: http://127.0.0.1:%d/%s/\n"
                "  serving %s (writes only %s); Ctrl+C stops it\n",
                port, token.c_str(), f.folder.c_str(), f.scad().c_str());
    std::fflush(stdout);
    if (!svr.listen_after_bind()) throw OutputError("clever-support view: the server stopped");
}

}  // namespace cs
