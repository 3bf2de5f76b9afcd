#pragma once
/// GET from a server's admin HTTP port on 127.0.0.1, the way an operator's script would: one
/// request per connection (Connection: close), read until the server closes.

#include <array>
#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/write.hpp>
#include <cstdint>
#include <string>

namespace ricochet::test {

/// The whole response to GET `path`, status line first.
inline std::string admin_response(std::uint16_t port, const std::string& path) {
  boost::asio::io_context io;
  boost::asio::ip::tcp::socket socket(io);
  socket.connect({boost::asio::ip::make_address("127.0.0.1"), port});
  const std::string request =
      "GET " + path + " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n";
  boost::asio::write(socket, boost::asio::buffer(request));
  std::string response;
  boost::system::error_code error;
  std::array<char, 4096> chunk{};
  while (!error) {
    const std::size_t size = socket.read_some(boost::asio::buffer(chunk), error);
    response.append(chunk.data(), size);
  }
  return response;
}

/// The status line of a response ("HTTP/1.1 200 OK").
inline std::string status_line(const std::string& response) {
  return response.substr(0, response.find("\r\n"));
}

/// The body of a response (all of it when it has no header end).
inline std::string body_of(const std::string& response) {
  const auto end = response.find("\r\n\r\n");
  return end == std::string::npos ? response : response.substr(end + 4);
}

/// The body of the response to GET `path`.
inline std::string admin_get(std::uint16_t port, const std::string& path) {
  return body_of(admin_response(port, path));
}

}  // namespace ricochet::test
