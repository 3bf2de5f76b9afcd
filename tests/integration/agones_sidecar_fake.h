#pragma once
/// A FAKE of the Agones SDK sidecar's REST gateway, for tests: the real sidecar is a Go binary
/// (agones-sdk) that runs beside the game server in a Kubernetes pod and is not available here.
/// It serves HTTP/1.1 on 127.0.0.1 (a port chosen free) the paths and bodies of Agones'
/// sdks/swagger/sdk.swagger.json that ricochet-server uses, checks them as the gateway would,
/// and records every call:
///
///   POST /ready           {}                           -> 200 {}   state Ready
///   POST /health          {}                           -> 200 {}
///   POST /allocate        {}                           -> 200 {}   state Allocated
///   POST /shutdown        {}                           -> 200 {}   state Shutdown
///   PUT  /metadata/label  {"key":"K","value":"V"}      -> 200 {}   label agones.dev/sdk-K = V
///   GET  /gameserver                                   -> 200 {"object_meta":{"labels":{..}},
///                                                                 "status":{"state":"..",
///                                                                 "address":"..","ports":[
///                                                                 {"name":"..","port":N}]}}
///   (address and ports as set_address() gave them; or any text, as answer_game_server() gave)
///
/// A body that is not the schema's (sdkEmpty, sdkKeyValue), a label value Kubernetes would
/// refuse, or a POST/PUT without Content-Type application/json gets 400; an unknown path 404.
/// Two failures to play: a sidecar that comes up late (the port is bound but not listening, so
/// a connect is refused, until listen()) and one that answers 500 to everything (fail()).

#include <sys/socket.h>
#include <sys/time.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/http.hpp>
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <regex>
#include <string>
#include <thread>
#include <vector>

namespace ricochet::test {

class FakeAgonesSidecar {
 public:
  struct Call {
    std::string method;
    std::string path;
    std::string body;
    unsigned status = 0;  ///< what the fake answered
    std::chrono::steady_clock::time_point at;
  };

  /// Binds 127.0.0.1 on a free port; accepts at once when `listening`, else only after listen()
  /// (until then a connect is refused, as before the sidecar starts).
  explicit FakeAgonesSidecar(bool listening = true) : acceptor_(io_) {
    namespace asio = boost::asio;
    acceptor_.open(asio::ip::tcp::v4());
    acceptor_.set_option(asio::ip::tcp::acceptor::reuse_address(true));
    acceptor_.bind({asio::ip::address_v4::loopback(), 0});
    port_ = acceptor_.local_endpoint().port();
    if (listening) listen();
  }
  ~FakeAgonesSidecar() {
    io_.stop();
    if (thread_.joinable()) thread_.join();
  }
  FakeAgonesSidecar(const FakeAgonesSidecar&) = delete;
  FakeAgonesSidecar& operator=(const FakeAgonesSidecar&) = delete;

  std::uint16_t port() const { return port_; }

  /// The sidecar comes up: connections are accepted from now on.
  void listen() {
    acceptor_.listen();
    accept();
    thread_ = std::thread([this] { io_.run(); });
  }
  /// While `failing`, every call is answered 500 (and changes nothing).
  void fail(bool failing) {
    const std::lock_guard lock(mutex_);
    failing_ = failing;
  }
  /// GET /gameserver's status.address and status.ports (name to port) from now on.
  void set_address(std::string address, std::map<std::string, int> ports) {
    const std::lock_guard lock(mutex_);
    address_ = std::move(address);
    ports_ = std::move(ports);
  }
  /// GET /gameserver is answered 200 with `body` from now on (a broken sidecar).
  void answer_game_server(std::string body) {
    const std::lock_guard lock(mutex_);
    game_server_body_ = std::move(body);
  }
  /// Runs on the fake's thread for every call, after it was answered.
  void on_call(std::function<void(const Call&)> observer) {
    const std::lock_guard lock(mutex_);
    observer_ = std::move(observer);
  }

  std::vector<Call> calls() const {
    const std::lock_guard lock(mutex_);
    return calls_;
  }
  /// Calls of `method path` answered `status` (0: any).
  int count(const std::string& method, const std::string& path, unsigned status = 200) const {
    const std::lock_guard lock(mutex_);
    int n = 0;
    for (const Call& call : calls_) {
      if (call.method == method && call.path == path && (status == 0 || call.status == status)) {
        ++n;
      }
    }
    return n;
  }
  /// The GameServer's labels, as the sidecar sets them ("agones.dev/sdk-map" ...).
  std::map<std::string, std::string> labels() const {
    const std::lock_guard lock(mutex_);
    return labels_;
  }
  /// "Scheduled", "Ready", "Allocated" or "Shutdown".
  std::string state() const {
    const std::lock_guard lock(mutex_);
    return state_;
  }

 private:
  void accept() {
    acceptor_.async_accept(
        [this](const boost::system::error_code& error, boost::asio::ip::tcp::socket socket) {
          if (error) return;
          serve(std::move(socket));
          accept();
        });
  }

  /// One request on a connection (the server closes it after the answer), read and answered
  /// here on the fake's thread: the server sends one call at a time.
  void serve(boost::asio::ip::tcp::socket socket) {
    namespace http = boost::beast::http;
    timeval limit{2, 0};  // a request that never completes does not hold the fake
    setsockopt(socket.native_handle(), SOL_SOCKET, SO_RCVTIMEO, &limit, sizeof limit);
    boost::beast::flat_buffer buffer;
    http::request<http::string_body> request;
    boost::system::error_code error;
    http::read(socket, buffer, request, error);
    if (error) return;
    Call call{std::string(request.method_string()), std::string(request.target()), request.body(),
              0, std::chrono::steady_clock::now()};
    std::string answer;
    std::function<void(const Call&)> observer;
    {
      const std::lock_guard lock(mutex_);
      call.status = route(request, answer);
      calls_.push_back(call);
      observer = observer_;
    }
    http::response<http::string_body> response{static_cast<http::status>(call.status), 11};
    response.set(http::field::content_type, "application/json");
    response.body() = answer;
    response.prepare_payload();
    http::write(socket, response, error);
    boost::system::error_code ignored;
    socket.shutdown(boost::asio::ip::tcp::socket::shutdown_both, ignored);
    if (observer) observer(call);
  }

  /// The status for `request` and its JSON answer; under mutex_.
  unsigned route(const boost::beast::http::request<boost::beast::http::string_body>& request,
                 std::string& answer) {
    namespace http = boost::beast::http;
    if (failing_) {
      answer = R"({"error":"the fake sidecar fails on purpose","code":13})";
      return 500;
    }
    const std::string target(request.target());
    const std::string body = trimmed(request.body());
    const bool json = request[http::field::content_type] == "application/json";
    answer = "{}";
    if (request.method() == http::verb::get && target == "/gameserver") {
      answer = game_server_body_ ? *game_server_body_ : game_server_json();
      return 200;
    }
    static const std::map<std::string, std::string> kStateAfter = {{"/ready", "Ready"},
                                                                   {"/health", ""},
                                                                   {"/allocate", "Allocated"},
                                                                   {"/shutdown", "Shutdown"}};
    if (const auto post = kStateAfter.find(target); post != kStateAfter.end()) {
      if (request.method() != http::verb::post) return 405;
      if (!json || body != "{}") return bad(answer, "the body must be sdkEmpty: {}");
      if (!post->second.empty()) state_ = post->second;
      return 200;
    }
    if (target == "/metadata/label") {
      if (request.method() != http::verb::put) return 405;
      static const std::regex kKeyValue(
          R"re(^\{\s*"key"\s*:\s*"([^"]*)"\s*,\s*"value"\s*:\s*"([^"]*)"\s*\}$)re");
      // A Kubernetes label value; the key gets the prefix agones.dev/sdk-.
      static const std::regex kLabelValue(R"(^([A-Za-z0-9]([-A-Za-z0-9_.]{0,61}[A-Za-z0-9])?)?$)");
      static const std::regex kLabelKey(R"(^[A-Za-z0-9]([-A-Za-z0-9_.]{0,40}[A-Za-z0-9])?$)");
      std::smatch fields;
      if (!json || !std::regex_match(body, fields, kKeyValue)) {
        return bad(answer, "the body must be sdkKeyValue: {\"key\":..,\"value\":..}");
      }
      const std::string key = fields[1].str();
      const std::string value = fields[2].str();
      if (!std::regex_match(key, kLabelKey) || !std::regex_match(value, kLabelValue)) {
        return bad(answer, "not a valid label");
      }
      labels_["agones.dev/sdk-" + key] = value;
      return 200;
    }
    answer = R"({"error":"Not Found","code":5})";
    return 404;
  }

  static unsigned bad(std::string& answer, const std::string& why) {
    answer = R"({"error":")" + why + R"(","code":3})";
    return 400;
  }

  static std::string trimmed(const std::string& text) {
    const auto first = text.find_first_not_of(" \t\r\n");
    if (first == std::string::npos) return "";
    return text.substr(first, text.find_last_not_of(" \t\r\n") - first + 1);
  }

  std::string game_server_json() const {
    std::string labels;
    for (const auto& [key, value] : labels_) {
      if (!labels.empty()) labels += ',';
      labels += "\"" + key + "\":\"" + value + "\"";
    }
    std::string ports;
    for (const auto& [name, port] : ports_) {
      if (!ports.empty()) ports += ',';
      ports += R"({"name":")" + name + R"(","port":)" + std::to_string(port) + "}";
    }
    return R"({"object_meta":{"name":"ricochet-fake","labels":{)" + labels +
           R"(}},"status":{"state":")" + state_ + R"(","address":")" + address_ + R"(","ports":[)" +
           ports + "]}}";
  }

  boost::asio::io_context io_;
  boost::asio::ip::tcp::acceptor acceptor_;
  std::uint16_t port_ = 0;
  std::thread thread_;
  mutable std::mutex mutex_;
  bool failing_ = false;
  std::function<void(const Call&)> observer_;
  std::vector<Call> calls_;
  std::map<std::string, std::string> labels_;
  std::string state_ = "Scheduled";
  std::string address_;
  std::map<std::string, int> ports_;
  std::optional<std::string> game_server_body_;
};

}  // namespace ricochet::test
