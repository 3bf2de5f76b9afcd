#include "admin_advertisement.h"

#include <boost/asio/ip/address.hpp>

namespace ricochet::server {
namespace {

/// "localhost" or a loopback address literal; a bind that is not an address counts as not.
bool is_loopback(const std::string& host) {
  if (host == "localhost") return true;
  boost::system::error_code error;
  const auto address = boost::asio::ip::make_address(host, error);
  return !error && address.is_loopback();
}

}  // namespace

std::int32_t advertised_admin_port(const AdminAdvertisement& admin) {
  if (admin.configured_port != 0) return admin.configured_port;
  if (admin.agones) return 0;
  if (!is_loopback(admin.bind)) return admin.bound_port;
  return is_loopback(admin.host) ? admin.bound_port : 0;
}

}  // namespace ricochet::server
