// What the server leaves on disk is its own (issue 29): the data directory 0700, the database
// and the generated TLS key 0600; and an admin token file that holds no token stops the start.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "server.h"
#include "temp_dir.h"

namespace ricochet::test::server_files_test {
namespace {

server::ServerConfig config_in(const std::filesystem::path& data_dir) {
  server::ServerConfig config;
  config.server.data_dir = data_dir.string();
  config.db.password_hashing = server::PasswordHashing::Minimum;
  config.control.bind = "127.0.0.1";
  config.control.port = 0;
  config.game.bind = "127.0.0.1";
  config.game.port = 0;
  config.admin.port = 0;
  config.matches.count = 0;
  config.matches.maps = {RICOCHET_SOURCE_DIR "/server/maps/arena.toml"};
  return config;
}

unsigned mode_of(const std::filesystem::path& path) {
  struct stat status {};
  EXPECT_EQ(::stat(path.c_str(), &status), 0) << path;
  return status.st_mode & 0777;
}

TEST(ServerFiles, TheDataDirectoryTheDatabaseAndTheKeyAreTheOwnersAlone) {
  TempDir dir{"ricochet-files"};
  const std::filesystem::path data = dir.path() / "data";
  { server::Server server(config_in(data)); }
  EXPECT_EQ(mode_of(data), 0700u);
  EXPECT_EQ(mode_of(data / "ricochet.db"), 0600u);
  EXPECT_EQ(mode_of(data / "control-key.pem"), 0600u);
}

TEST(ServerFiles, AnAdminTokenFileWithoutATokenStopsTheStart) {
  TempDir dir{"ricochet-files"};
  server::ServerConfig config = config_in(dir.path() / "data");
  config.admin.token_file = (dir.path() / "token").string();
  std::ofstream(config.admin.token_file) << " \n";
  try {
    server::Server server(config);
    ADD_FAILURE() << "the server started with an empty token file";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("is empty"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace ricochet::test::server_files_test
