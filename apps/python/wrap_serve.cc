// rigel.Server: `rigel serve` inside a Python process (the server library,
// apps/server), so the build functions this process registered
// (rigel.register_function, plugin folders) are in the graph editor's
// palette and run when the editor builds. The HTTP server runs on a thread
// of its own; Python functions it calls take the GIL (wrap_build_graph.cc).

#include <atomic>
#include <chrono>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "common.h"
#include "http_server.h"
#include "rigel/app/scene_files.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/rig/manager.h"
#include "rigel/tools/data_files.h"
#include "workspace.h"

namespace rigel::python {

namespace fs = std::filesystem;
namespace {

class Server {
 public:
  Server(const std::string& scene, const std::string& root, const std::string& host, int port, const std::string& token,
         const std::string& web, const std::vector<std::string>& rigs, bool log) {
    std::unique_ptr<scene::Scene> s;
    fs::path scene_path;
    if (scene.empty()) {
      s = std::make_unique<scene::Scene>(ephemeral::default_registry());
    } else {
      s = unwrap(app::open_scene(scene));
      if (app::is_scene_file(scene)) scene_path = fs::absolute(scene);
    }
    for (const std::string& def : rigs) unwrap(rig::add_rig(*s, fs::absolute(def), tools::components()));
    s->graph().clear_history();
    std::error_code ec;
    if (!fs::is_directory(root, ec)) raise(ErrorCode::kInvalidArgument, "root: '" + root + "' is not a folder");
    workspace_ = std::make_unique<server::Workspace>(std::move(s), scene_path, fs::absolute(root), tools::components());
    if (!scene.empty()) workspace_->set_character(fs::absolute(scene).lexically_normal());
    server::ServeOptions options;
    options.host = host;
    options.port = port;
    options.token = token;
    options.web_dir = web;
    options.log = log;
    http_ = std::make_unique<server::HttpServer>(*workspace_, options);
    port_ = unwrap(http_->bind());
    url_ = "http://" + (host.find(':') != std::string::npos ? "[" + host + "]" : host) + ":" + std::to_string(port_) +
           "/" + (token.empty() ? "" : "?token=" + token);
    thread_ = std::thread([this] {
      result_ = http_->run();
      done_ = true;
    });
  }
  ~Server() { stop(); }
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  int port() const { return port_; }
  const std::string& url() const { return url_; }
  bool running() const { return thread_.joinable() && !done_; }

  void stop() {
    if (!thread_.joinable()) return;
    py::gil_scoped_release release;  // a request may be running a Python function
    http_->stop();
    thread_.join();
  }
  // Serves until stop() or Ctrl-C (KeyboardInterrupt, after stopping).
  void wait() {
    while (running()) {
      {
        py::gil_scoped_release release;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
      if (PyErr_CheckSignals() != 0) {
        stop();
        throw py::error_already_set();
      }
    }
    stop();
    check(result_);
  }

 private:
  std::unique_ptr<server::Workspace> workspace_;
  std::unique_ptr<server::HttpServer> http_;
  std::thread thread_;
  std::atomic<bool> done_{false};
  Status result_;
  int port_ = 0;
  std::string url_;
};

}  // namespace

void wrap_serve(py::module_& m) {
  py::class_<Server>(m, "Server", R"(`rigel serve` in this process: the web app and the JSON API over a scene, on a
thread of its own, so the build functions this process registered (rigel.register_function,
rigel.load_plugins) are in the graph editor's palette and run when it builds. Use
rigel.serve(), which picks the token and the web app, and loads the root's plugins/.)")
      .def(py::init<const std::string&, const std::string&, const std::string&, int, const std::string&,
                    const std::string&, const std::vector<std::string>&, bool>(),
           py::arg("scene") = "", py::arg("root") = ".", py::arg("host") = "127.0.0.1", py::arg("port") = 0,
           py::arg("token") = "", py::arg("web") = "", py::arg("rigs") = std::vector<std::string>{},
           py::arg("log") = false,
           "Opens the scene (a .rigel or a character; empty: an empty scene), builds the rigs, binds and starts "
           "serving. A host other than loopback needs a token.")
      .def_property_readonly("port", &Server::port)
      .def_property_readonly("url", &Server::url)
      .def_property_readonly("running", &Server::running)
      .def("stop", &Server::stop, "Stops serving (waits for the request in flight).")
      .def("wait", &Server::wait, "Serves until stop() from another thread, or Ctrl-C.")
      .def("__enter__", [](Server& s) -> Server& { return s; }, py::return_value_policy::reference)
      .def("__exit__", [](Server& s, py::args) { s.stop(); });
  m.attr("WEB_DIR") = RIGEL_WEB_DIR;
}

}  // namespace rigel::python
