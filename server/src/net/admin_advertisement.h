#pragma once
/// Which admin port this server's fleet directory row advertises (db::GameServerRow::admin_port):
/// one that readers of the directory (ricochet-loadtest --fleet, a dashboard) can reach at the
/// row's host, or none (0). In order:
///
///   advertise_admin_port set   → it ([placement]; behind NAT or a proxy, or a Kubernetes Service
///                                that routes to the pod's admin port)
///   under Agones               → 0: the row's host is the node's address, where only the Fleet's
///                                ports (control, game) are published; the admin port is a plain
///                                container port, reached inside the cluster (deploy/README.md)
///   bound beyond loopback      → the bound port (0.0.0.0, ::, or an address of this machine)
///   bound to loopback          → the bound port when the row's host is loopback too (one machine:
///                                tests, ./tools/run.sh), else 0: nobody elsewhere reaches it

#include <cstdint>
#include <string>

namespace ricochet::server {

struct AdminAdvertisement {
  std::string bind;              ///< admin.bind: an IP address literal
  std::uint16_t bound_port = 0;  ///< the admin port as bound
  std::string host;              ///< the row's host (a DNS name or an IP address)
  int configured_port = 0;       ///< [placement] advertise_admin_port; 0: unset
  bool agones = false;           ///< the server runs under Agones (AGONES_SDK_HTTP_PORT)
};

/// The admin port to advertise, 0..65535; 0: none.
std::int32_t advertised_admin_port(const AdminAdvertisement& admin);

}  // namespace ricochet::server
