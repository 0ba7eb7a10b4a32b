// Browser sessions and API tokens over HTTP (auth/access.hpp, auth/token_store.hpp).
#include "params/json_fields.hpp"
#include "routes/handlers.hpp"

namespace trailscope::server::handlers {

namespace {

nlohmann::json who_json(const Principal& who) {
  return {{"owner", who.owner}, {"role", role_name(who.role)}};
}

// Answers that carry a session or a token are never cached.
Response private_json(int status, const nlohmann::json& j) {
  Response r = Response::json(status, j);
  r.headers.emplace_back("Cache-Control", "no-store");
  return r;
}

}  // namespace

Response get_session(App& app, const Request& req, const PathParams&) {
  reject_unknown_params(req, {});
  nlohmann::json j = who_json(req.principal);
  j["signed_in"] = !req.principal.anonymous();
  j["public_reads"] = app.access->public_reads();
  return private_json(200, j);
}

Response create_session(App& app, const Request& req, const PathParams&) {
  const nlohmann::json body = parse_body_object(req.body, {"login", "token"});
  if (body.contains("login") == body.contains("token"))
    throw invalid_argument(
        "body", "body: give either \"login\" (the code of the sign-in URL the server printed) or \"token\"");
  const Access::Session s =
      body.contains("login")
          ? app.access->sign_in_with_code(string_field(body, "login"), req.remote_address)
          : app.access->sign_in_with_token(string_field(body, "token"), req.remote_address);
  Response r = private_json(200, who_json(s.who));
  r.headers.emplace_back("Set-Cookie", Access::session_cookie(s.secret));
  return r;
}

Response delete_session(App& app, const Request& req, const PathParams&) {
  app.access->sign_out(req);
  Response r = Response::no_content();
  r.headers.emplace_back("Set-Cookie", Access::cleared_session_cookie());
  return r;
}

Response list_tokens(App& app, const Request& req, const PathParams&) {
  reject_unknown_params(req, {});
  nlohmann::json list = nlohmann::json::array();
  for (const auto& t : app.access->tokens().list()) list.push_back(t.to_json());
  return private_json(200, {{"tokens", list}});
}

Response create_token(App& app, const Request& req, const PathParams&) {
  const nlohmann::json body = parse_body_object(req.body, {"name", "role"});
  const std::string name = string_field(body, "name");
  const Role role = parse_token_role(string_field(body, "role"), "role");
  const IssuedToken t = app.access->tokens().create(name, role);
  nlohmann::json j = t.record.to_json();
  j["token"] = t.token;
  Response r = private_json(201, j);
  r.headers.emplace_back("Location", "/api/v1/tokens/" + t.record.id);
  return r;
}

Response revoke_token(App& app, const Request&, const PathParams& p) {
  const std::string& id = p.at("token");
  if (!app.access->revoke(id)) throw not_found("token", "token '" + id + "' does not exist");
  return Response::no_content();
}

}  // namespace trailscope::server::handlers
