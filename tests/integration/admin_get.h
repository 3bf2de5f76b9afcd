#pragma once
/// Requests to a server's admin HTTP port on 127.0.0.1, the way an operator's script makes them:
/// one request per connection (Connection: close), read until the server closes.

#include <array>
#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/write.hpp>
#include <cstdint>
#include <string>

namespace ricochet::test {

/// The whole response to `method` `path` (no body), status line first; with "Authorization:
/// Bearer `token`" unless it is empty.
inline std::string admin_response(std::uint16_t port, const std::string& path,
                                  const std::string& method = "GET",
                                  const std::string& token = "") {
  boost::asio::io_context io;
  boost::asio::ip::tcp::socket socket(io);
  socket.connect({boost::asio::ip::make_address("127.0.0.1"), port});
  std::string request = method + " " + path + " HTTP/1.1\r\nHost: 127.0.0.1\r\n";
  if (!token.empty()) request += "Authorization: Bearer " + token + "\r\n";
  request += "Content-Length: 0\r\nConnection: close\r\n\r\n";
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
