#include "cutdyn/server/server.hpp"

#include <httplib.h>
#include <sys/socket.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <future>
#include <map>
#include <mutex>
#include <thread>
#include <vector>

#include "cutdyn/core/error.hpp"
#include "cutdyn/server/api.hpp"

namespace cutdyn::server {

namespace detail {
struct WebFile {
  std::string_view path, content_type, text;
};
const std::vector<WebFile>& web_files();  // generated from web/ (cmake/embed_web.cmake)
}  // namespace detail

namespace {

// The workers that run the jobs, first come first served.
class Workers {
 public:
  explicit Workers(int count) {
    for (int i = 0; i < count; ++i) threads_.emplace_back([this] { work(); });
  }
  ~Workers() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      done_ = true;
    }
    ready_.notify_all();
    for (std::thread& t : threads_) t.join();
  }
  std::future<Response> submit(std::function<Response()> job) {
    auto task = std::make_shared<std::packaged_task<Response()>>(std::move(job));
    std::future<Response> result = task->get_future();
    {
      std::lock_guard<std::mutex> lock(mutex_);
      queue_.push_back([task] { (*task)(); });
    }
    ready_.notify_one();
    return result;
  }

 private:
  void work() {
    for (;;) {
      std::function<void()> job;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        ready_.wait(lock, [this] { return done_ || !queue_.empty(); });
        if (done_ && queue_.empty()) return;
        job = std::move(queue_.front());
        queue_.pop_front();
      }
      job();
    }
  }
  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<std::function<void()>> queue_;
  std::vector<std::thread> threads_;
  bool done_ = false;
};

// The cancel flag of each page's latest request of each kind.
class Latest {
 public:
  using Flag = std::shared_ptr<std::atomic<bool>>;
  // A new request of `key`: the older one still running is cancelled.
  Flag start(const std::string& key) {
    auto flag = std::make_shared<std::atomic<bool>>(false);
    if (key.empty()) return flag;
    std::lock_guard<std::mutex> lock(mutex_);
    Flag& slot = latest_[key];
    if (slot) *slot = true;
    slot = flag;
    return flag;
  }
  void finish(const std::string& key, const Flag& flag) {
    if (key.empty()) return;
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = latest_.find(key);
    if (it != latest_.end() && it->second == flag) latest_.erase(it);
  }

 private:
  std::mutex mutex_;
  std::map<std::string, Flag> latest_;
};

// "a=1&b=x%20y" → {a: 1, b: "x y"} (percent-decoding, + as a space; the last of a repeated key).
std::map<std::string, std::string> parse_query(const std::string& text) {
  const auto decode = [](std::string_view s) {
    std::string out;
    for (std::size_t i = 0; i < s.size(); ++i) {
      if (s[i] == '+') {
        out += ' ';
      } else if (s[i] == '%' && i + 2 < s.size() &&
                 std::isxdigit(static_cast<unsigned char>(s[i + 1])) &&
                 std::isxdigit(static_cast<unsigned char>(s[i + 2]))) {
        out += static_cast<char>(std::stoi(std::string(s.substr(i + 1, 2)), nullptr, 16));
        i += 2;
      } else {
        out += s[i];
      }
    }
    return out;
  };
  std::map<std::string, std::string> query;
  std::size_t at = 0;
  while (at <= text.size()) {
    const std::size_t end = std::min(text.find('&', at), text.size());
    const std::string_view pair(text.data() + at, end - at);
    if (!pair.empty()) {
      const auto eq = pair.find('=');
      query[decode(pair.substr(0, eq))] =
          eq == std::string_view::npos ? std::string() : decode(pair.substr(eq + 1));
    }
    at = end + 1;
  }
  return query;
}

int worker_count(int requested) {
  if (requested > 0) return requested;
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

}  // namespace

struct Server::State {
  State(io::Case start, ServerOptions o)
      : options(std::move(o)),
        api(std::move(start), options.data_folder),
        workers(worker_count(options.workers)) {}
  ServerOptions options;
  Api api;
  Workers workers;
  Latest latest;
  httplib::Server http;
  int port = 0;
  int listening_socket = -1;  // as httplib made it, to raise its backlog

  void answer(const httplib::Request& req, httplib::Response& res) {
    const auto started = std::chrono::steady_clock::now();
    // The query of the target only: a form body's fields are not parameters.
    const auto question = req.target.find('?');
    Request request{req.method, req.path,
                    question == std::string::npos ? std::map<std::string, std::string>{}
                                                  : parse_query(req.target.substr(question + 1)),
                    req.body};
    const std::string page = req.get_header_value("X-Cutdyn-Page");
    const std::string key = page.empty() ? std::string() : page + " " + req.path;
    const Latest::Flag cancel = latest.start(key);
    Response r =
        workers.submit([this, request, cancel] { return api.handle(request, cancel.get()); }).get();
    latest.finish(key, cancel);
    res.status = r.status;
    res.set_content(r.body, r.content_type);
    res.set_header("Cache-Control", "no-store");
    log(req, r.status, started);
  }

  void log(const httplib::Request& req, int status,
           std::chrono::steady_clock::time_point started) const {
    if (!options.log) return;
    const std::chrono::duration<double, std::milli> ms = std::chrono::steady_clock::now() - started;
    options.log(req.method, req.path, status, ms.count());
  }
};

Server::Server(io::Case start, ServerOptions options)
    : state_(std::make_unique<State>(std::move(start), std::move(options))) {
  State& s = *state_;
  s.http.set_payload_max_length(s.options.max_body_bytes);
  // SO_REUSEADDR (a restart need not wait for TIME_WAIT) but not SO_REUSEPORT, which would let
  // a second server share a port in use instead of being refused.
  s.http.set_socket_options([&s](int sock) {
    int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
    s.listening_socket = sock;
  });
  const auto api = [&s](const httplib::Request& req, httplib::Response& res) {
    s.answer(req, res);
  };
  s.http.Get("/api/.*", api);
  s.http.Post("/api/.*", api);
  s.http.Get("/", [&s](const httplib::Request& req, httplib::Response& res) {
    res.set_redirect("/index.html");
    s.log(req, 302, std::chrono::steady_clock::now());
  });
  for (const detail::WebFile& f : detail::web_files())
    s.http.Get(std::string(f.path), [&s, f](const httplib::Request& req, httplib::Response& res) {
      res.set_content(f.text.data(), f.text.size(), std::string(f.content_type).c_str());
      s.log(req, 200, std::chrono::steady_clock::now());
    });
  s.http.set_error_handler([](const httplib::Request& req, httplib::Response& res) {
    if (!res.body.empty()) return;
    const Response r{res.status, "application/json",
                     "{\"error\": \"request: " + req.method + " " + req.path + ": " +
                         (res.status == 413 ? std::string("the body is too large")
                                            : std::string("no such page or request")) +
                         "\"}"};
    res.set_content(r.body, r.content_type);
  });
}

Server::~Server() { stop(); }

void Server::bind() {
  State& s = *state_;
  if (s.options.port == 0) {
    s.port = s.http.bind_to_any_port(s.options.host);
  } else {
    s.port = s.http.bind_to_port(s.options.host, s.options.port) ? s.options.port : -1;
  }
  // httplib listens with a backlog of 5: a burst of connections (the page's requests, a load
  // test) would overflow it, and a connection whose handshake is dropped long enough is reset.
  // Listening again on the bound socket only raises the backlog.
  if (s.port > 0 && s.listening_socket >= 0) ::listen(s.listening_socket, SOMAXCONN);
  if (s.port <= 0)
    throw InvalidInput(
        {"cannot listen on " + s.options.host + ":" + std::to_string(s.options.port) +
         " (in use, or not an address of this machine); choose another --port"},
        "serve");
}

int Server::port() const { return state_->port; }

void Server::run() { state_->http.listen_after_bind(); }

void Server::stop() {
  if (state_->http.is_running()) state_->http.stop();
}

}  // namespace cutdyn::server
