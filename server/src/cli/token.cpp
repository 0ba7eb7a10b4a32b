// `trailscope token create|list|revoke`: the API tokens of a data folder (auth/token_store.hpp). A running
// server sees the changes within a second; revoking a token ends the sessions signed in with it.
#include <ctime>
#include <iomanip>
#include <iostream>
#include <memory>

#include "auth/token_store.hpp"
#include "cli/commands.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/json_text.hpp"

namespace trailscope::cli {
namespace fs = std::filesystem;
using namespace trailscope::server;

namespace {

fs::path tokens_file(const std::string& data_dir) {
  return fs::path(data_dir) / "tokens.json";
}

std::string utc_text(std::int64_t unix_seconds) {
  const std::time_t t = static_cast<std::time_t>(unix_seconds);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

}  // namespace

void add_token(CLI::App& app) {
  auto* cmd = app.add_subcommand("token", "Create, list and revoke the API tokens of a data folder");
  cmd->require_subcommand(1);
  cmd->footer(
      "A token is sent as 'Authorization: Bearer tsk_...'. Roles: reader (reads), writer (also creates, and\n"
      "deletes what it created), admin (also deletes anything and manages tokens). The data folder keeps "
      "only\n"
      "an Argon2id hash of each token: the token text is shown once, when it is created.");

  struct Opts {
    std::string data_dir = default_data_dir(), name, role, id;
    bool json = false;
  };
  auto o = std::make_shared<Opts>();

  auto* create = cmd->add_subcommand("create", "Create a token and print it (once)");
  create->add_option("--data-dir", o->data_dir, "data folder of the server")->capture_default_str();
  create->add_option("--name", o->name, "owner name (1-64 of A-Z a-z 0-9 . _ @ -)")->required();
  create->add_option("--role", o->role, "reader | writer | admin")->required();
  create->add_flag("--json", o->json, "print {\"id\",\"name\",\"role\",\"token\"}");
  create->callback([o] {
    const Role role = parse_token_role(o->role, "role");
    TokenStore store(tokens_file(o->data_dir));
    const IssuedToken t = store.create(o->name, role);
    if (o->json) {
      std::cout << json_text({{"id", t.record.id},
                              {"name", t.record.name},
                              {"role", role_name(t.record.role)},
                              {"token", t.token}})
                << std::endl;
      return;
    }
    std::cout << "created token " << t.record.id << " for '" << t.record.name << "' ("
              << role_name(t.record.role) << "); shown once, store it now:\n"
              << t.token << std::endl;
  });

  auto* list = cmd->add_subcommand("list", "List the tokens (ids, names, roles; never secrets)");
  list->add_option("--data-dir", o->data_dir, "data folder of the server")->capture_default_str();
  list->add_flag("--json", o->json, "print a JSON array of {\"id\",\"name\",\"role\",\"created\"}");
  list->callback([o] {
    const TokenStore store(tokens_file(o->data_dir));
    const auto tokens = store.list();
    if (o->json) {
      nlohmann::json out = nlohmann::json::array();
      for (const auto& t : tokens) out.push_back(t.to_json());
      std::cout << json_text(out) << std::endl;
      return;
    }
    if (tokens.empty()) {
      std::cout << "no tokens in " << tokens_file(o->data_dir).string() << "\n";
      return;
    }
    std::cout << std::left << std::setw(14) << "ID" << std::setw(24) << "NAME" << std::setw(8) << "ROLE"
              << "CREATED (UTC)\n";
    for (const auto& t : tokens)
      std::cout << std::setw(14) << t.id << std::setw(24) << t.name << std::setw(8) << role_name(t.role)
                << utc_text(t.created) << "\n";
  });

  auto* revoke =
      cmd->add_subcommand("revoke", "Revoke a token by its id (a running server stops accepting it)");
  revoke->add_option("--data-dir", o->data_dir, "data folder of the server")->capture_default_str();
  revoke->add_option("id", o->id, "the token's id (12 hex digits, as `token list` shows)")->required();
  revoke->callback([o] {
    TokenStore store(tokens_file(o->data_dir));
    if (!store.revoke(o->id))
      throw not_found("id", "no token '" + o->id + "' in " + tokens_file(o->data_dir).string());
    std::cout << "revoked token " << o->id << std::endl;
  });
}

}  // namespace trailscope::cli
