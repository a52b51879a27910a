// `cutdyn serve`: the stability explorer in the browser (docs/explorer.md). The server is the
// library's (cutdyn/server/server.hpp); this file reads the flags, starts it and stops it on
// Ctrl-C or SIGTERM.
#include <pthread.h>
#include <spawn.h>

#include <CLI/CLI.hpp>
#include <csignal>
#include <memory>
#include <thread>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cutdyn/core/error.hpp"
#include "cutdyn/server/server.hpp"

extern char** environ;

namespace cutdyn::cli {
namespace {

struct ServeArgs {
  std::string case_path;
  std::string host = "127.0.0.1";
  int port = 8080;
  bool open = false;
  bool quiet = false;
  std::string data;  // --data DIR: the files a request's case may name
};

// Opens `url` in the desktop's browser, if there is one to ask.
bool open_browser(const std::string& url) {
  pid_t pid = 0;
  std::string program = "xdg-open";
  char* argv[] = {program.data(), const_cast<char*>(url.c_str()), nullptr};
  return posix_spawnp(&pid, "xdg-open", nullptr, nullptr, argv, environ) == 0;
}

int run_serve(const ServeArgs& args, std::ostream& out, std::ostream& err) {
  if (args.port < 0 || args.port > 65535)
    throw InvalidInput({"--port = " + std::to_string(args.port) + ": must be 0 to 65535"},
                       "command line");
  io::Case c = load_case(args.case_path, "milling-insperger", err);
  // SIGINT and SIGTERM go to one thread, which stops the server; every other thread (the
  // server's) is started with them blocked.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  // A client that goes away while being answered must not end the server.
  std::signal(SIGPIPE, SIG_IGN);
  server::ServerOptions options;
  options.host = args.host;
  options.port = args.port;
  options.data_folder = args.data;
  if (!args.quiet)
    options.log = [&err](const std::string& method, const std::string& path, int status,
                         double ms) {
      err << "cutdyn serve: " << method << " " << path << " " << status << " " << ms << " ms\n";
    };
  server::Server server(std::move(c), options);
  server.bind();
  const std::string url = "http://" + args.host + ":" + std::to_string(server.port()) + "/";
  out << "cutdyn serve: " << url << " (Ctrl-C to stop)" << std::endl;
  if (args.host != "127.0.0.1" && args.host != "localhost" && args.host != "::1")
    err << "cutdyn: warning: command line: --host " << args.host
        << ": the explorer is reachable from other machines; it has no authentication\n";
  if (args.open && !open_browser(url))
    err << "cutdyn: warning: command line: --open: no browser to open (xdg-open); open " << url
        << " yourself\n";
  std::thread stopper([&server, signals] {
    int signal = 0;
    sigwait(&signals, &signal);
    server.stop();
  });
  server.run();
  // Stopped by a signal: the stopper has returned. Stopped otherwise: wake it.
  pthread_kill(stopper.native_handle(), SIGTERM);
  stopper.join();
  out << "cutdyn serve: stopped" << std::endl;
  return 0;
}

}  // namespace

std::function<int(std::ostream&, std::ostream&)> add_serve_command(CLI::App& app) {
  auto args = std::make_shared<ServeArgs>();
  auto* c = app.add_subcommand("serve", "the stability explorer in the browser, on 127.0.0.1");
  c->add_option("CASE", args->case_path,
                "the starting case (TOML), or a built-in example's name (default "
                "milling-insperger)");
  c->add_option("--port", args->port, "port (default 8080; 0: any free port)");
  c->add_option("--host", args->host,
                "address to listen on (default 127.0.0.1: this machine only)");
  c->add_flag("--open", args->open, "open the page in the desktop's browser");
  c->add_flag("--quiet", args->quiet, "do not log each request on stderr");
  c->add_option("--data", args->data,
                "a folder whose files (FRFs) the cases sent by the page may name, by their path "
                "within it; without it, only the starting case's own [[frf]] files");
  return [c, args](std::ostream& out, std::ostream& err) -> int {
    if (!c->parsed()) return -1;
    return run_serve(*args, out, err);
  };
}

}  // namespace cutdyn::cli
