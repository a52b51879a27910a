// The web explorer's HTTP server (`cutdyn serve`; docs/explorer.md): the page, compiled into
// the binary, and the JSON API (api.hpp) on one port of 127.0.0.1 by default.
//
// Requests are read on the server's request threads; the jobs run on its own workers (one
// per core), so that reading and answering never wait for a computation. A request that names
// its page (header X-Cutdyn-Page) cancels the same page's older request of the same kind that
// is still computing: the older one is answered 409. Bodies above max_body_bytes are refused
// (413) before they are read.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <string>

#include "cutdyn/io/case_file.hpp"

namespace cutdyn::server {

struct ServerOptions {
  std::string host = "127.0.0.1";
  int port = 8080;  // 0: any free port (see Server::port())
  std::size_t max_body_bytes = 1 << 20;
  int workers = 0;  // threads that run the jobs; 0: one per core
  /// The folder whose files a request's case may name in [[frf]] (api.hpp); none when empty.
  std::filesystem::path data_folder;
  /// Each request answered: method, path, status, milliseconds (for a log).
  std::function<void(const std::string&, const std::string&, int, double)> log;
};

class Server {
 public:
  Server(io::Case start, ServerOptions options);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  /// Binds the port. Throws InvalidInput naming the host and port when it cannot.
  void bind();
  /// The port bound (after bind()).
  int port() const;
  /// Answers requests until stop() (from another thread or a signal handler's thread).
  void run();
  void stop();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace cutdyn::server
