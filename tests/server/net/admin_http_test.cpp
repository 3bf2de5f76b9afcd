#include "admin_http.h"

#include <gtest/gtest.h>
#include <poll.h>

#include <atomic>
#include <boost/asio/connect.hpp>
#include <boost/asio/read.hpp>
#include <boost/asio/write.hpp>
#include <chrono>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace ricochet::server::admin_http_test {
namespace {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;
using namespace std::chrono_literals;

/// A blocking client socket to the server, every read bounded by 3 s (poll() first: Asio's
/// blocking reads retry past SO_RCVTIMEO).
class Client {
 public:
  /// Connects from `from`, an address of the loopback net (127.0.0.0/8): another address than
  /// 127.0.0.1 is another proto::HostKey to the server.
  explicit Client(std::uint16_t port, const char* from = "127.0.0.1") : socket_(io_) {
    socket_.open(tcp::v4());
    socket_.bind({asio::ip::make_address(from), 0});
    socket_.connect({asio::ip::make_address("127.0.0.1"), port});
  }
  void send(const std::string& bytes) { asio::write(socket_, asio::buffer(bytes)); }
  /// Everything until the server closes (or nothing comes for 3 s).
  std::string read_to_end() {
    std::string received;
    char chunk[4096];
    boost::system::error_code error;
    for (;;) {
      const std::size_t n = read_some(asio::buffer(chunk), error);
      if (error) break;
      received.append(chunk, n);
    }
    closed_by_server_ = error == asio::error::eof || error == asio::error::connection_reset;
    return received;
  }
  /// One response of `Content-Length` bytes, leaving the connection open; empty when the
  /// server closed the connection or went quiet for 3 s first.
  std::string read_response() {
    std::string received;
    boost::system::error_code error;
    char c;
    while (received.find("\r\n\r\n") == std::string::npos) {
      if (read_some(asio::buffer(&c, 1), error) == 0) return {};
      received += c;
    }
    const auto at = received.find("Content-Length: ");
    std::string body(std::stoul(received.substr(at + 16)), '\0');
    for (std::size_t got = 0; got < body.size();) {
      const std::size_t n = read_some(asio::buffer(body.data() + got, body.size() - got), error);
      if (n == 0) return {};
      got += n;
    }
    return received + body;
  }
  bool closed_by_server() const { return closed_by_server_; }
  /// What has arrived, without waiting (empty when nothing has).
  std::string read_available() {
    std::string received;
    char chunk[4096];
    while (socket_.available() > 0) {
      boost::system::error_code error;
      const std::size_t n = socket_.read_some(asio::buffer(chunk), error);
      if (error) break;
      received.append(chunk, n);
    }
    return received;
  }

 private:
  /// Some bytes, or an error (timed_out after 3 s of nothing).
  std::size_t read_some(asio::mutable_buffer buffer, boost::system::error_code& error) {
    pollfd readable{socket_.native_handle(), POLLIN, 0};
    if (::poll(&readable, 1, 3000) <= 0) {
      error = asio::error::timed_out;
      return 0;
    }
    return socket_.read_some(buffer, error);
  }

  asio::io_context io_;
  tcp::socket socket_;
  bool closed_by_server_ = false;
};

std::string status_line(const std::string& response) {
  return response.substr(0, response.find("\r\n"));
}

std::string body_of(const std::string& response) {
  const auto at = response.find("\r\n\r\n");
  return at == std::string::npos ? std::string{} : response.substr(at + 4);
}

/// Waits up to 2 s for `condition`: the server may count after the client already saw the close.
template <class Condition>
bool eventually(Condition condition) {
  const auto deadline = std::chrono::steady_clock::now() + 2s;
  while (!condition()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(1ms);
  }
  return true;
}

std::string get(const std::string& target) {
  return "GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n";
}

class AdminHttpTest : public ::testing::Test {
 protected:
  void start(AdminHttpOptions options = {}) {
    options.port = 0;
    options.clock = [this] { return now_.load(); };
    server_.emplace(
        io_, options, metrics_,
        AdminHttpCallbacks{[this] { return healthy_.load(); }, [this] { return ready_.load(); },
                           [this](AccountAction action, std::function<void(AdminReply)> answer) {
                             {
                               const std::lock_guard lock(actions_mutex_);
                               actions_.push_back(action);
                             }
                             answer({200, std::string(action.ban ? "banned " : "unbanned ") +
                                              action.username + "\n"});
                           },
                           fleet_});
    for (const AdminRoute& route : routes_) server_->add_route(route);
    ASSERT_FALSE(server_->start());
    port_ = server_->local_endpoint().port();
    ASSERT_NE(port_, 0);
    thread_ = std::thread{[this] { io_.run(); }};
  }
  void TearDown() override {
    server_.reset();
    work_.reset();
    if (thread_.joinable()) thread_.join();
  }
  /// Moves the server's fake clock on and has every connection look at its deadline.
  void advance(std::chrono::microseconds by) {
    now_ += by.count();
    server_->check_deadlines();
  }
  std::string exchange(const std::string& request, const char* from = "127.0.0.1") {
    Client client{port_, from};
    client.send(request);
    return client.read_to_end();
  }

  std::atomic<proto::TimeUs> now_{5 * proto::kMicrosPerSecond};  ///< stands still unless advanced
  asio::io_context io_;
  std::optional<asio::executor_work_guard<asio::io_context::executor_type>> work_{
      asio::make_work_guard(io_)};
  MetricsRegistry metrics_;
  std::atomic<bool> healthy_{true};
  std::atomic<bool> ready_{false};
  std::mutex actions_mutex_;
  std::vector<AccountAction> actions_;  ///< what the account callback was asked, in order
  std::vector<AdminRoute> routes_;      ///< added before start()
  /// The /fleet callback given to start(); empty: none (/fleet is 404).
  std::function<void(std::function<void(AdminReply)>)> fleet_;
  std::optional<AdminHttp> server_;
  std::thread thread_;
  std::uint16_t port_ = 0;
};

TEST_F(AdminHttpTest, MetricsServesTheRegistryInTextFormat) {
  metrics_.gauge("ricochet_matches", "Matches open.").set(4);
  start();
  const std::string response = exchange(get("/metrics"));
  EXPECT_EQ(status_line(response), "HTTP/1.1 200 OK");
  EXPECT_NE(response.find("Content-Type: text/plain; version=0.0.4; charset=utf-8\r\n"),
            std::string::npos)
      << response;
  const std::string body = body_of(response);
  EXPECT_NE(body.find("# TYPE ricochet_matches gauge\nricochet_matches 4\n"), std::string::npos)
      << body;
  EXPECT_NE(body.find("ricochet_admin_rejected_total{reason=\"timeout\"} 0\n"), std::string::npos)
      << body;
}

TEST_F(AdminHttpTest, HealthzFollowsTheHealthCallback) {
  start();
  std::string response = exchange(get("/healthz"));
  EXPECT_EQ(status_line(response), "HTTP/1.1 200 OK");
  EXPECT_EQ(body_of(response), "ok\n");
  healthy_ = false;
  response = exchange(get("/healthz"));
  EXPECT_EQ(status_line(response), "HTTP/1.1 503 Service Unavailable");
  EXPECT_EQ(body_of(response), "not ticking on time\n");
}

TEST_F(AdminHttpTest, ReadyzFollowsTheReadyCallback) {
  start();
  EXPECT_EQ(status_line(exchange(get("/readyz"))), "HTTP/1.1 503 Service Unavailable");
  ready_ = true;
  const std::string response = exchange(get("/readyz?verbose=1"));
  EXPECT_EQ(status_line(response), "HTTP/1.1 200 OK");
  EXPECT_EQ(body_of(response), "ready\n");
}

TEST_F(AdminHttpTest, UnknownPathIs404AndOtherMethodsAre405) {
  start();
  EXPECT_EQ(status_line(exchange(get("/"))), "HTTP/1.1 404 Not Found");
  EXPECT_EQ(status_line(exchange(get("/metricsx"))), "HTTP/1.1 404 Not Found");
  const std::string response = exchange(
      "POST /metrics HTTP/1.1\r\nHost: x\r\nContent-Length: 2\r\nConnection: close\r\n\r\nhi");
  EXPECT_EQ(status_line(response), "HTTP/1.1 405 Method Not Allowed");
  EXPECT_NE(response.find("Allow: GET\r\n"), std::string::npos) << response;
  EXPECT_EQ(
      status_line(exchange("DELETE /healthz HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n")),
      "HTTP/1.1 405 Method Not Allowed");
  EXPECT_EQ(server_->rejected(AdminRejectReason::NotFound), 2u);
  EXPECT_EQ(server_->rejected(AdminRejectReason::MethodNotAllowed), 2u);
}

TEST_F(AdminHttpTest, KeepAliveServesSeveralRequestsOnOneConnection) {
  start();
  Client client{port_};
  for (int i = 0; i < 3; ++i) {
    client.send("GET /healthz HTTP/1.1\r\nHost: x\r\n\r\n");
    EXPECT_EQ(status_line(client.read_response()), "HTTP/1.1 200 OK");
  }
  EXPECT_TRUE(eventually([&] { return server_->responses() == 3; }));
}

TEST_F(AdminHttpTest, OversizedHeadersAre431AndClosed) {
  AdminHttpOptions options;
  options.max_request_bytes = 1024;
  start(options);
  Client client{port_};
  client.send("GET /metrics HTTP/1.1\r\nHost: x\r\nX-Padding: " + std::string(4000, 'a') +
              "\r\n\r\n");
  const std::string response = client.read_to_end();
  EXPECT_EQ(status_line(response), "HTTP/1.1 431 Request Header Fields Too Large");
  EXPECT_TRUE(client.closed_by_server());
  EXPECT_EQ(server_->rejected(AdminRejectReason::Oversized), 1u);
}

TEST_F(AdminHttpTest, OversizedBodyIs413AndClosed) {
  AdminHttpOptions options;
  options.max_request_bytes = 1024;
  start(options);
  // Appended, not "..." + std::string(5000, 'b'): GCC 12's -Warray-bounds misreads that at -O3.
  std::string request = "GET /metrics HTTP/1.1\r\nHost: x\r\nContent-Length: 5000\r\n\r\n";
  request.append(5000, 'b');
  const std::string response = exchange(request);
  EXPECT_EQ(status_line(response), "HTTP/1.1 413 Payload Too Large");
  EXPECT_EQ(server_->rejected(AdminRejectReason::Oversized), 1u);
}

TEST_F(AdminHttpTest, MalformedRequestIs400AndClosed) {
  start();
  Client client{port_};
  client.send("BLAH\r\n\r\n");
  EXPECT_EQ(status_line(client.read_to_end()), "HTTP/1.1 400 Bad Request");
  EXPECT_TRUE(client.closed_by_server());
  EXPECT_EQ(server_->rejected(AdminRejectReason::Malformed), 1u);
}

TEST_F(AdminHttpTest, SlowRequestIsClosedAtTheDeadline) {
  AdminHttpOptions options;
  options.request_timeout = 200ms;
  start(options);
  Client client{port_};
  client.send("GET /metrics HTTP/1.1\r\nHost: x\r\n");  // never finishes the headers
  ASSERT_TRUE(eventually([&] { return server_->connections() == 1; }));  // accepted: it counts
  advance(200ms);
  EXPECT_EQ(client.read_to_end(), "");
  EXPECT_TRUE(client.closed_by_server());
  EXPECT_TRUE(eventually([&] { return server_->rejected(AdminRejectReason::Timeout) == 1; }));
}

TEST_F(AdminHttpTest, ARequestFinishedJustBeforeItsDeadlineIsAnswered) {
  AdminHttpOptions options;
  options.request_timeout = 200ms;
  start(options);
  Client client{port_};
  client.send("GET /healthz HTTP/1.1\r\nHost: x\r\n");
  ASSERT_TRUE(eventually([&] { return server_->connections() == 1; }));
  advance(200ms - 1us);
  client.send("\r\n");
  EXPECT_EQ(status_line(client.read_response()), "HTTP/1.1 200 OK");
  EXPECT_EQ(server_->rejected(AdminRejectReason::Timeout), 0u);
}

TEST_F(AdminHttpTest, IdleKeepAliveConnectionIsClosedAtTheDeadline) {
  AdminHttpOptions options;
  options.request_timeout = 200ms;
  start(options);
  Client client{port_};
  client.send("GET /healthz HTTP/1.1\r\nHost: x\r\n\r\n");
  EXPECT_EQ(status_line(client.read_response()), "HTTP/1.1 200 OK");
  ASSERT_TRUE(eventually([&] { return server_->responses() == 1; }));  // the next one's runs
  advance(200ms);
  EXPECT_EQ(client.read_to_end(), "");
  EXPECT_TRUE(client.closed_by_server());
  EXPECT_TRUE(eventually([&] { return server_->rejected(AdminRejectReason::Timeout) == 1; }));
}

TEST_F(AdminHttpTest, AConnectionAboveTheCapClosesTheOneWaitingLongest) {
  AdminHttpOptions options;
  options.max_connections = 1;
  options.max_connections_per_address = 1;
  start(options);
  Client first{port_};
  first.send("GET /healthz HTTP/1.1\r\nHost: x\r\n\r\n");
  EXPECT_EQ(status_line(first.read_response()), "HTTP/1.1 200 OK");  // now idle (keep-alive)
  Client second{port_};
  second.send(get("/healthz"));
  EXPECT_EQ(status_line(second.read_to_end()), "HTTP/1.1 200 OK");
  EXPECT_EQ(first.read_to_end(), "");
  EXPECT_TRUE(first.closed_by_server());
  EXPECT_EQ(server_->rejected(AdminRejectReason::TooManyFromAddress), 1u);
}

/// Connections that are opened and never used, `count` of them, once the server holds as many
/// as it keeps.
std::vector<std::unique_ptr<Client>> idle_connections(std::uint16_t port, int count) {
  std::vector<std::unique_ptr<Client>> idle;
  for (int i = 0; i < count; ++i) idle.push_back(std::make_unique<Client>(port));
  return idle;
}

TEST_F(AdminHttpTest, SeventeenIdleConnectionsDoNotStarveHealthz) {
  // One address may hold every slot here (16), as a proxy in front of the port would.
  AdminHttpOptions options;
  options.max_connections = 16;
  options.max_connections_per_address = 16;
  start(options);
  const auto idle = idle_connections(port_, 17);
  ASSERT_TRUE(eventually([&] {
    return server_->rejected(AdminRejectReason::TooManyFromAddress) == 1 &&
           server_->connections() == 16;
  }));
  Client probe{port_};
  probe.send(get("/healthz"));
  EXPECT_EQ(status_line(probe.read_to_end()), "HTTP/1.1 200 OK");
  EXPECT_LE(server_->connections(), 16u);
}

TEST_F(AdminHttpTest, OneAddressHoldsAtMostItsConnections) {
  start();  // 8 per address
  const auto idle = idle_connections(port_, 17);
  ASSERT_TRUE(eventually([&] {
    return server_->rejected(AdminRejectReason::TooManyFromAddress) == 9 &&
           server_->connections() == 8;
  }));
  Client probe{port_};
  probe.send(get("/healthz"));
  EXPECT_EQ(status_line(probe.read_to_end()), "HTTP/1.1 200 OK");
  // The oldest of them went first: the first idle connection is closed.
  EXPECT_EQ(idle.front()->read_to_end(), "");
  EXPECT_TRUE(idle.front()->closed_by_server());
}

TEST_F(AdminHttpTest, MetricsNeedsTheBearerTokenAndProbesDoNot) {
  AdminHttpOptions options;
  options.bearer_token = "s3cret-token";
  start(options);
  const std::string without = exchange(get("/metrics"));
  EXPECT_EQ(status_line(without), "HTTP/1.1 401 Unauthorized");
  EXPECT_NE(without.find("WWW-Authenticate: Bearer"), std::string::npos) << without;
  const auto with = [](const std::string& authorization) {
    return "GET /metrics HTTP/1.1\r\nHost: x\r\nAuthorization: " + authorization +
           "\r\nConnection: close\r\n\r\n";
  };
  EXPECT_EQ(status_line(exchange(with("Bearer s3cret-tokeN"))), "HTTP/1.1 401 Unauthorized");
  EXPECT_EQ(status_line(exchange(with("Bearer s3cret-token-and-more"))),
            "HTTP/1.1 401 Unauthorized");
  EXPECT_EQ(status_line(exchange(with("Basic s3cret-token"))), "HTTP/1.1 401 Unauthorized");
  EXPECT_EQ(status_line(exchange(with("Bearer s3cret-token"))), "HTTP/1.1 200 OK");
  EXPECT_EQ(status_line(exchange(get("/healthz"))), "HTTP/1.1 200 OK");
  EXPECT_EQ(server_->rejected(AdminRejectReason::Unauthorized), 4u);
}

std::string post(const std::string& target, const std::string& token = "") {
  return "POST " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\n" +
         (token.empty() ? std::string() : "Authorization: Bearer " + token + "\r\n") +
         "Content-Length: 0\r\nConnection: close\r\n\r\n";
}

TEST_F(AdminHttpTest, AnAccountActionIsAnsweredOnceTheCallbackHasDoneIt) {
  start();
  const std::string ban = exchange(post("/accounts/Mallory_1.x-y/ban"));
  EXPECT_EQ(status_line(ban), "HTTP/1.1 200 OK");
  EXPECT_EQ(body_of(ban), "banned Mallory_1.x-y\n");
  EXPECT_EQ(body_of(exchange(post("/accounts/mallory/unban"))), "unbanned mallory\n");
  EXPECT_EQ(status_line(exchange(get("/accounts/mallory/ban"))), "HTTP/1.1 405 Method Not Allowed");
  for (const char* bad : {"/accounts/mal%20lory/ban", "/accounts//ban", "/accounts/mallory/kick",
                          "/accounts/mallory", "/accounts/mallory/ban/x"}) {
    EXPECT_EQ(status_line(exchange(post(bad))), "HTTP/1.1 404 Not Found") << bad;
  }
  const std::lock_guard lock(actions_mutex_);
  ASSERT_EQ(actions_.size(), 2u);
  EXPECT_TRUE(actions_[0].ban);
  EXPECT_EQ(actions_[0].operator_address, "127.0.0.1");
  EXPECT_FALSE(actions_[1].ban);
}

TEST_F(AdminHttpTest, AccountActionsNeedTheBearerTokenWhenOneIsSet) {
  AdminHttpOptions options;
  options.bearer_token = "s3cret-token";
  start(options);
  EXPECT_EQ(status_line(exchange(post("/accounts/mallory/ban"))), "HTTP/1.1 401 Unauthorized");
  EXPECT_EQ(status_line(exchange(post("/accounts/mallory/ban", "s3cret-tokeN"))),
            "HTTP/1.1 401 Unauthorized");
  EXPECT_EQ(status_line(exchange(post("/accounts/mallory/ban", "s3cret-token"))),
            "HTTP/1.1 200 OK");
  EXPECT_EQ(server_->rejected(AdminRejectReason::Unauthorized), 2u);
  const std::lock_guard lock(actions_mutex_);
  EXPECT_EQ(actions_.size(), 1u);
}

TEST_F(AdminHttpTest, AccountActionsAreForbiddenBeyondLoopbackWithoutAToken) {
  AdminHttpOptions options;
  options.bind = "0.0.0.0";  // exposed, and no token configured
  start(options);
  const std::string refused = exchange(post("/accounts/mallory/ban"));
  EXPECT_EQ(status_line(refused), "HTTP/1.1 403 Forbidden");
  EXPECT_NE(body_of(refused).find("admin.token_file"), std::string::npos) << refused;
  EXPECT_EQ(server_->rejected(AdminRejectReason::Forbidden), 1u);
  EXPECT_EQ(status_line(exchange(get("/healthz"))), "HTTP/1.1 200 OK");
  const std::lock_guard lock(actions_mutex_);
  EXPECT_TRUE(actions_.empty());
}

TEST_F(AdminHttpTest, FleetIs404WithoutItsCallback) {
  start();  // a server that keeps no directory row
  EXPECT_EQ(status_line(exchange(get("/fleet"))), "HTTP/1.1 404 Not Found");
}

TEST_F(AdminHttpTest, FleetIsAnsweredByItsCallbackBehindTheToken) {
  // The callback answers later, from another thread, as the DB worker does.
  std::vector<std::thread> answering;
  std::atomic<int> asked{0};
  fleet_ = [&](std::function<void(AdminReply)> answer) {
    const int n = ++asked;
    answering.emplace_back([n, answer = std::move(answer)] {
      if (n == 2) return answer({503, "the database could not answer now\n"});
      answer({200, R"({"servers":[]})", "application/json"});
    });
  };
  AdminHttpOptions options;
  options.bearer_token = "s3cret-token";
  start(options);
  const auto with_token = [](const std::string& method) {
    return method + " /fleet HTTP/1.1\r\nHost: x\r\nAuthorization: Bearer s3cret-token\r\n" +
           "Content-Length: 0\r\nConnection: close\r\n\r\n";
  };
  EXPECT_EQ(status_line(exchange(get("/fleet"))), "HTTP/1.1 401 Unauthorized");
  const std::string listed = exchange(with_token("GET"));
  EXPECT_EQ(status_line(listed), "HTTP/1.1 200 OK");
  EXPECT_NE(listed.find("Content-Type: application/json"), std::string::npos) << listed;
  EXPECT_EQ(body_of(listed), R"({"servers":[]})");
  EXPECT_EQ(status_line(exchange(with_token("GET"))), "HTTP/1.1 503 Service Unavailable");
  EXPECT_EQ(status_line(exchange(with_token("POST"))), "HTTP/1.1 405 Method Not Allowed");
  EXPECT_EQ(asked.load(), 2);
  EXPECT_EQ(server_->rejected(AdminRejectReason::Unauthorized), 1u);
  for (std::thread& thread : answering) thread.join();
}

TEST_F(AdminHttpTest, StopClosesOpenConnectionsAndTheListener) {
  start();
  Client client{port_};
  client.send("GET /healthz HTTP/1.1\r\nHost: x\r\n\r\n");
  EXPECT_EQ(status_line(client.read_response()), "HTTP/1.1 200 OK");
  server_->stop();
  EXPECT_EQ(client.read_to_end(), "");
  EXPECT_TRUE(client.closed_by_server());
  EXPECT_THROW(Client{port_}, boost::system::system_error);
}

TEST_F(AdminHttpTest, StartReportsABindError) {
  start();
  AdminHttpOptions taken;
  taken.port = port_;
  AdminHttp second{io_, taken, metrics_, {}};
  EXPECT_EQ(second.start(), asio::error::address_in_use);
}

}  // namespace
}  // namespace ricochet::server::admin_http_test

namespace ricochet::server::admin_http_test {
namespace {

/// Two pages, a script and the sign-in page, as dashboard_files() lists its own.
constexpr EmbeddedFile kFiles[] = {
    {"/app.js", "text/javascript; charset=utf-8", "\"js-1\"", "export {};\n"},
    {"/index.html", "text/html; charset=utf-8", "\"html-1\"", "<!doctype html><p>overview\n"},
    {"/signin.html", "text/html; charset=utf-8", "\"signin-1\"", "<!doctype html><form>\n"},
};

std::string header_of(const std::string& response, const std::string& name) {
  const auto at = response.find("\r\n" + name + ": ");
  if (at == std::string::npos) return {};
  const auto start = at + name.size() + 4;
  return response.substr(start, response.find("\r\n", start) - start);
}

std::string get_with(const std::string& target, const std::string& headers) {
  return "GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\n" + headers +
         "Connection: close\r\n\r\n";
}

std::string post_form(const std::string& target, const std::string& body,
                      const std::string& headers = "") {
  return "POST " + target +
         " HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/x-www-form-urlencoded\r\n" +
         headers + "Content-Length: " + std::to_string(body.size()) +
         "\r\nConnection: close\r\n\r\n" + body;
}

AdminRoute json_route(std::string path, bool prefix, std::string body) {
  AdminRoute route;
  route.path = std::move(path);
  route.prefix = prefix;
  // Answered at once (an answer from another thread takes the account actions' path, tested
  // above).
  route.handler = [body = std::move(body)](const AdminRequest& request, AdminAnswer answer) {
    answer({200, body + " " + request.path + "?" + request.query, "application/json"});
  };
  return route;
}

TEST_F(AdminHttpTest, FilesAreServedWithTheirTypeAnETagAndTheSecurityHeaders) {
  AdminHttpOptions options;
  options.files = kFiles;
  start(options);
  const std::string page = exchange(get("/"));
  EXPECT_EQ(status_line(page), "HTTP/1.1 200 OK");
  EXPECT_EQ(body_of(page), "<!doctype html><p>overview\n");
  EXPECT_EQ(header_of(page, "Content-Type"), "text/html; charset=utf-8");
  EXPECT_EQ(header_of(page, "ETag"), "\"html-1\"");
  EXPECT_EQ(header_of(page, "Cache-Control"), "no-cache");
  EXPECT_EQ(header_of(page, "Content-Security-Policy"),
            "default-src 'self'; base-uri 'none'; form-action 'self'; frame-ancestors 'none'");
  EXPECT_EQ(header_of(page, "X-Content-Type-Options"), "nosniff");
  const std::string script = exchange(get("/app.js"));
  EXPECT_EQ(header_of(script, "Content-Type"), "text/javascript; charset=utf-8");
  EXPECT_EQ(body_of(script), "export {};\n");
  // The browser holds this version: 304, no body; another version: the file.
  const std::string fresh = exchange(get_with("/app.js", "If-None-Match: \"js-1\"\r\n"));
  EXPECT_EQ(status_line(fresh), "HTTP/1.1 304 Not Modified");
  EXPECT_EQ(body_of(fresh), "");
  EXPECT_EQ(header_of(fresh, "ETag"), "\"js-1\"");
  EXPECT_EQ(status_line(exchange(get_with("/app.js", "If-None-Match: \"js-0\"\r\n"))),
            "HTTP/1.1 200 OK");
  EXPECT_EQ(status_line(exchange(get("/app.jsx"))), "HTTP/1.1 404 Not Found");
  // Every response has the headers, a refusal too.
  EXPECT_EQ(header_of(exchange(get("/nothing")), "X-Content-Type-Options"), "nosniff");
}

TEST_F(AdminHttpTest, RoutesTakeExactPathsThenTheLongestPrefixAndTheirMethod) {
  routes_ = {json_route("/api/replays/", true, "list"), json_route("/api/replays/x/", true, "x"),
             json_route("/api/overview", false, "overview")};
  start();
  std::string response = exchange(get("/api/overview?since=3"));
  EXPECT_EQ(status_line(response), "HTTP/1.1 200 OK");
  EXPECT_EQ(header_of(response, "Content-Type"), "application/json");
  EXPECT_EQ(body_of(response), "overview /api/overview?since=3");
  EXPECT_EQ(body_of(exchange(get("/api/replays/7"))), "list /api/replays/7?");
  EXPECT_EQ(body_of(exchange(get("/api/replays/x/9"))), "x /api/replays/x/9?");
  EXPECT_EQ(status_line(exchange(get("/api/overview/more"))), "HTTP/1.1 404 Not Found");
  response = exchange(post_form("/api/overview", "a=1"));
  EXPECT_EQ(status_line(response), "HTTP/1.1 405 Method Not Allowed");
  EXPECT_EQ(header_of(response, "Allow"), "GET");
}

TEST_F(AdminHttpTest, OnePathTakesARoutePerMethod) {
  AdminRoute act = json_route("/api/recordings/", true, "act");
  act.method = "POST";
  routes_ = {json_route("/api/recordings/", true, "read"), act,
             json_route("/api/recordings/x/", true, "x")};
  start();
  EXPECT_EQ(body_of(exchange(get("/api/recordings/7"))), "read /api/recordings/7?");
  EXPECT_EQ(body_of(exchange(post_form("/api/recordings/7/replay", ""))),
            "act /api/recordings/7/replay?");
  // The longer prefix still wins; its one method is GET.
  const std::string response = exchange(post_form("/api/recordings/x/1", ""));
  EXPECT_EQ(status_line(response), "HTTP/1.1 405 Method Not Allowed");
  EXPECT_EQ(header_of(response, "Allow"), "GET");
}

TEST_F(AdminHttpTest, WithATokenABrowserSignsInForASessionThatExpires) {
  AdminHttpOptions options;
  options.files = kFiles;
  options.public_files = {"/signin.html"};
  options.bearer_token = "s3cret token";
  options.session_lifetime = std::chrono::minutes(10);
  routes_ = {json_route("/api/overview", false, "overview")};
  start(options);
  // Without it: a page is sent to the sign-in form, the rest refused; the form is open.
  std::string response = exchange(get("/"));
  EXPECT_EQ(status_line(response), "HTTP/1.1 303 See Other");
  EXPECT_EQ(header_of(response, "Location"), "/signin");
  EXPECT_EQ(status_line(exchange(get("/app.js"))), "HTTP/1.1 401 Unauthorized");
  EXPECT_EQ(status_line(exchange(get("/api/overview"))), "HTTP/1.1 401 Unauthorized");
  EXPECT_EQ(status_line(exchange(get("/metrics"))), "HTTP/1.1 401 Unauthorized");
  EXPECT_EQ(body_of(exchange(get("/signin"))), "<!doctype html><form>\n");
  EXPECT_EQ(server_->rejected(AdminRejectReason::Unauthorized), 4U);
  // A made-up cookie, or a wrong token, is no way in.
  EXPECT_EQ(status_line(exchange(get_with(
                "/api/overview", "Cookie: ricochet_session=" + std::string(64, '0') + "\r\n"))),
            "HTTP/1.1 401 Unauthorized");
  EXPECT_EQ(status_line(exchange(post_form("/signin", "token=s3cret"))),
            "HTTP/1.1 401 Unauthorized");
  EXPECT_EQ(status_line(exchange(post_form("/signin", "token=%zz"))), "HTTP/1.1 401 Unauthorized");
  // The token, form-encoded: a session in an HttpOnly, SameSite=Strict cookie.
  response = exchange(post_form("/signin", "other=1&token=s3cret+token"));
  EXPECT_EQ(status_line(response), "HTTP/1.1 303 See Other");
  EXPECT_EQ(header_of(response, "Location"), "/");
  const std::string set_cookie = header_of(response, "Set-Cookie");
  ASSERT_EQ(set_cookie.substr(0, 17), "ricochet_session=") << response;
  EXPECT_NE(set_cookie.find("; HttpOnly; SameSite=Strict; Max-Age=600"), std::string::npos)
      << set_cookie;
  EXPECT_EQ(set_cookie.find("s3cret"), std::string::npos) << set_cookie;
  const std::string cookie = "Cookie: theme=dark; " + set_cookie.substr(0, 17 + 64) + "\r\n";
  EXPECT_EQ(status_line(exchange(get_with("/", cookie))), "HTTP/1.1 200 OK");
  EXPECT_EQ(status_line(exchange(get_with("/app.js", cookie))), "HTTP/1.1 200 OK");
  EXPECT_EQ(body_of(exchange(get_with("/api/overview", cookie))), "overview /api/overview?");
  EXPECT_EQ(status_line(exchange(get_with("/metrics", cookie))), "HTTP/1.1 200 OK");
  // Scripts use the bearer header.
  EXPECT_EQ(
      status_line(exchange(get_with("/api/overview", "Authorization: Bearer s3cret token\r\n"))),
      "HTTP/1.1 200 OK");
  // The session ends at its lifetime, on the server's clock.
  advance(std::chrono::minutes(10));
  EXPECT_EQ(status_line(exchange(get_with("/api/overview", cookie))), "HTTP/1.1 401 Unauthorized");
  // Signing out ends one before.
  response = exchange(post_form("/signin", "token=s3cret+token"));
  const std::string again =
      "Cookie: " + header_of(response, "Set-Cookie").substr(0, 17 + 64) + "\r\n";
  EXPECT_EQ(status_line(exchange(get_with("/api/overview", again))), "HTTP/1.1 200 OK");
  EXPECT_EQ(status_line(exchange(post_form("/signout", "", again))), "HTTP/1.1 303 See Other");
  EXPECT_EQ(status_line(exchange(get_with("/api/overview", again))), "HTTP/1.1 401 Unauthorized");
}

TEST_F(AdminHttpTest, WrongTokensFromOneAddressAreLimitedWhileAnotherSignsIn) {
  EpisodeLog episodes;
  AdminHttpOptions options;
  options.files = kFiles;
  options.public_files = {"/signin.html"};
  options.bearer_token = "s3cret token";
  options.max_signin_failures = 3;
  options.signin_window = std::chrono::seconds(60);
  options.episodes = &episodes;
  start(options);
  constexpr const char* kGuesser = "127.0.0.2";
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(
        status_line(exchange(post_form("/signin", "token=guess" + std::to_string(i)), kGuesser)),
        "HTTP/1.1 401 Unauthorized");
  }
  // Its fourth guess in the minute is not looked at.
  std::string response = exchange(post_form("/signin", "token=guess3"), kGuesser);
  EXPECT_EQ(status_line(response), "HTTP/1.1 429 Too Many Requests");
  EXPECT_EQ(header_of(response, "Retry-After"), "60");
  EXPECT_EQ(header_of(response, "Content-Type"), "text/html; charset=utf-8");
  EXPECT_NE(body_of(response).find("Too many wrong tokens from your address. Try again in 60 s."),
            std::string::npos)
      << response;
  // The operator, at another address, signs in meanwhile.
  response = exchange(post_form("/signin", "token=s3cret+token"));
  EXPECT_EQ(status_line(response), "HTTP/1.1 303 See Other");
  EXPECT_EQ(header_of(response, "Set-Cookie").substr(0, 17), "ricochet_session=");
  // One episode of each refusal, both the guesser's: logged once each.
  EXPECT_EQ(episodes.open_episodes(now_.load()), 2U);
  // The right token from the guesser is refused too until its minute ends: had it been let in,
  // the answers would tell a right guess from the wrong ones, and guessing would go on at full
  // speed.
  advance(std::chrono::milliseconds(59'500));
  response = exchange(post_form("/signin", "token=s3cret+token"), kGuesser);
  EXPECT_EQ(status_line(response), "HTTP/1.1 429 Too Many Requests");
  EXPECT_EQ(header_of(response, "Retry-After"), "1");
  EXPECT_EQ(header_of(response, "Set-Cookie"), "");
  EXPECT_EQ(server_->rejected(AdminRejectReason::SignInLimited), 2U);
  EXPECT_EQ(server_->rejected(AdminRejectReason::Unauthorized), 3U);
  EXPECT_NE(body_of(exchange(get_with("/metrics", "Authorization: Bearer s3cret token\r\n")))
                .find("ricochet_admin_rejected_total{reason=\"sign_in_limited\"} 2\n"),
            std::string::npos);
  // The minute is over: the limit lifts.
  advance(std::chrono::milliseconds(500));
  EXPECT_EQ(status_line(exchange(post_form("/signin", "token=s3cret+token"), kGuesser)),
            "HTTP/1.1 303 See Other");
}

TEST_F(AdminHttpTest, AStreamSendsWhatItsProducerPushesAsServerSentEvents) {
  std::mutex mutex;
  std::shared_ptr<AdminEventStream> stream;
  AdminRoute route;
  route.path = "/api/events";
  route.stream = [&](const AdminRequest&, std::shared_ptr<AdminEventStream> opened) {
    const std::lock_guard lock(mutex);
    stream = std::move(opened);
  };
  routes_ = {route};
  start();
  Client client{port_};
  client.send(get("/api/events"));
  ASSERT_TRUE(eventually([&] {
    const std::lock_guard lock(mutex);
    return stream != nullptr;
  }));
  {
    const std::lock_guard lock(mutex);
    EXPECT_TRUE(stream->push("{\"a\":1}"));
    EXPECT_TRUE(stream->push("two\nlines"));
  }
  std::string received;
  ASSERT_TRUE(eventually([&] {
    received += client.read_available();
    return received.find("data: two lines\n\n") != std::string::npos;
  })) << received;
  EXPECT_EQ(status_line(received), "HTTP/1.1 200 OK");
  EXPECT_EQ(header_of(received, "Content-Type"), "text/event-stream");
  EXPECT_EQ(header_of(received, "X-Content-Type-Options"), "nosniff");
  EXPECT_NE(received.find("\r\n\r\ndata: {\"a\":1}\n\ndata: two lines\n\n"), std::string::npos)
      << received;
  // The server stops: the stream closes, and the producer is told.
  server_->stop();
  EXPECT_TRUE(eventually([&] {
    const std::lock_guard lock(mutex);
    return stream->closed();
  }));
  const std::lock_guard lock(mutex);
  EXPECT_FALSE(stream->push("late"));
}

TEST_F(AdminHttpTest, BeforeStreamAnswersInsteadOfOpeningTheStreamOrLetsItOpen) {
  std::atomic<int> opened{0};
  AdminRoute route;
  route.path = "/api/matches/";
  route.prefix = true;
  route.before_stream = [](const AdminRequest& request) -> std::optional<AdminReply> {
    if (request.path == "/api/matches/1/live") return std::nullopt;
    if (request.path == "/api/matches/1/map") return AdminReply{200, "{}", "application/json"};
    return AdminReply{404, "no such match\n"};
  };
  route.stream = [&opened](const AdminRequest&, std::shared_ptr<AdminEventStream> stream) {
    ++opened;
    stream->push("frame");
  };
  routes_ = {route};
  start();
  std::string response = exchange(get("/api/matches/9/live"));
  EXPECT_EQ(status_line(response), "HTTP/1.1 404 Not Found");
  EXPECT_EQ(body_of(response), "no such match\n");
  EXPECT_EQ(header_of(response, "X-Content-Type-Options"), "nosniff");
  response = exchange(get("/api/matches/1/map"));
  EXPECT_EQ(status_line(response), "HTTP/1.1 200 OK");
  EXPECT_EQ(header_of(response, "Content-Type"), "application/json");
  EXPECT_EQ(opened.load(), 0);
  Client client{port_};
  client.send(get("/api/matches/1/live"));
  std::string received;
  ASSERT_TRUE(eventually([&] {
    received += client.read_available();
    return received.find("data: frame\n\n") != std::string::npos;
  })) << received;
  EXPECT_EQ(header_of(received, "Content-Type"), "text/event-stream");
  EXPECT_EQ(opened.load(), 1);
}

/// A stream route whose streams stay open and quiet, as a dashboard tab's between events.
AdminRoute quiet_stream(std::string path) {
  AdminRoute route;
  route.path = std::move(path);
  route.stream = [](const AdminRequest&, std::shared_ptr<AdminEventStream>) {};
  return route;
}

/// Asks for `target` on `client` and returns the status line of what comes back first (empty
/// when the server closed the connection or said nothing within 2 s).
std::string status_of(Client& client, const std::string& request) {
  client.send(request);
  std::string received;
  eventually([&] {
    received += client.read_available();
    return received.find("\r\n\r\n") != std::string::npos;
  });
  return status_line(received);
}

std::string keep_alive_get(const std::string& target) {
  return "GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n";
}

TEST_F(AdminHttpTest, ABrowsersFourTabsHoldTheirStreamsAndStillLoadPages) {
  routes_ = {quiet_stream("/api/overview/events"), json_route("/api/overview", false, "overview")};
  start();  // the defaults: 8 connections and 4 streams per address
  // Four tabs, each with its stream open, as a browser holds them: each a connection of its own
  // that never goes idle.
  std::vector<std::unique_ptr<Client>> tabs;
  for (int i = 0; i < 4; ++i) {
    tabs.push_back(std::make_unique<Client>(port_));
    EXPECT_EQ(status_of(*tabs.back(), get("/api/overview/events")), "HTTP/1.1 200 OK") << i;
  }
  // The browser's two other connections (6 a host) load pages and JSON meanwhile.
  Client first{port_};
  Client second{port_};
  for (int i = 0; i < 3; ++i) {
    first.send(keep_alive_get("/api/overview"));
    EXPECT_EQ(status_line(first.read_response()), "HTTP/1.1 200 OK") << i;
    second.send(keep_alive_get("/healthz"));
    EXPECT_EQ(status_line(second.read_response()), "HTTP/1.1 200 OK") << i;
  }
  EXPECT_EQ(server_->rejected(AdminRejectReason::TooManyFromAddress), 0U);
  // A fifth stream is refused; the tabs' streams stay.
  Client fifth{port_};
  fifth.send(get("/api/overview/events"));
  const std::string refused = fifth.read_to_end();
  EXPECT_EQ(status_line(refused), "HTTP/1.1 503 Service Unavailable");
  EXPECT_EQ(body_of(refused), "at most 4 live pages from one address at once; close one\n");
  EXPECT_EQ(server_->rejected(AdminRejectReason::TooManyStreams), 1U);
  EXPECT_TRUE(eventually([&] { return server_->connections() == 6; }));
  // A tab closed (reloaded) frees its stream at once, with no event written to find it gone: the
  // reloaded tab's new stream opens.
  tabs.front().reset();
  EXPECT_TRUE(eventually([&] { return server_->connections() == 5; }));
  Client reloaded{port_};
  EXPECT_EQ(status_of(reloaded, get("/api/overview/events")), "HTTP/1.1 200 OK");
  EXPECT_EQ(server_->rejected(AdminRejectReason::TooManyStreams), 1U);
}

TEST_F(AdminHttpTest, OneAddressOpeningStreamsAndConnectionsCannotKeepAnotherOut) {
  AdminHttpOptions options;
  options.max_connections = 14;  // under the 4 streams and 8 others one address may hold
  routes_ = {quiet_stream("/api/overview/events")};
  start(options);
  constexpr const char* kGreedy = "127.0.0.2";
  std::vector<std::unique_ptr<Client>> greedy;
  int opened = 0;
  for (int i = 0; i < 12; ++i) {
    greedy.push_back(std::make_unique<Client>(port_, kGreedy));
    opened += status_of(*greedy.back(), get("/api/overview/events")) == "HTTP/1.1 200 OK" ? 1 : 0;
  }
  EXPECT_EQ(opened, 4);
  for (int i = 0; i < 12; ++i) greedy.push_back(std::make_unique<Client>(port_, kGreedy));
  ASSERT_TRUE(eventually([&] { return server_->connections() <= 12; }));
  // Another address gets in, its stream too.
  EXPECT_EQ(status_line(exchange(get("/healthz"))), "HTTP/1.1 200 OK");
  Client tab{port_};
  EXPECT_EQ(status_of(tab, get("/api/overview/events")), "HTTP/1.1 200 OK");
}

TEST(AdminEventStream, AReaderThatFallsMaxQueueBehindIsDropped) {
  AdminEventStream stream{3};
  int wakes = 0;
  stream.on_wake([&wakes] { ++wakes; });
  EXPECT_TRUE(stream.push("1"));
  EXPECT_TRUE(stream.push("2"));
  EXPECT_EQ(stream.take(), (std::deque<std::string>{"1", "2"}));
  EXPECT_TRUE(stream.push("3"));
  EXPECT_TRUE(stream.push("4"));
  EXPECT_TRUE(stream.push("5"));
  EXPECT_FALSE(stream.overflowed());
  // A fourth unsent: closed, never waited for.
  EXPECT_FALSE(stream.push("6"));
  EXPECT_TRUE(stream.closed());
  EXPECT_TRUE(stream.overflowed());
  EXPECT_TRUE(stream.take().empty());
  EXPECT_FALSE(stream.push("7"));
  EXPECT_EQ(wakes, 6);
}

}  // namespace
}  // namespace ricochet::server::admin_http_test
