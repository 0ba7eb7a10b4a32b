#pragma once
// The one rule of ownership: a resource (a dataset, graph, bundle, video, run, MOT file, sweep, sector set,
// replay or job) records the owner name of the caller that created it (Request::principal.owner), and only
// that owner or an admin may delete it (or cancel it, for a job). A resource with no owner ("": made before
// owners were recorded, or by the command line or the demo) belongs to the admins alone. Every delete
// handler asks here, after the lookup that answers 404 (a writer may learn that a resource exists, not
// change it); the stores only keep the owner string.
#include <string>

#include "routes/http_types.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::server {

/// True when `who` may delete or cancel a resource whose owner is `owner`: an admin always; another caller
/// when it has a token and `owner` is its own, non-empty, owner name.
inline bool may_modify(const Principal& who, const std::string& owner) {
  return who.role == Role::admin || (!owner.empty() && who.may_modify(owner));
}

/// Throws Error(forbidden, param) unless the caller of `req` may_modify() the resource `noun` `id` owned by
/// `owner`, e.g. "dataset 'x' belongs to 'alice'; only its owner or an admin may delete it". `verb`:
/// "delete" or "cancel".
inline void require_owner(const Request& req, const std::string& param, const std::string& noun,
                          const std::string& id, const std::string& owner,
                          const std::string& verb = "delete") {
  if (may_modify(req.principal, owner)) return;
  const std::string what = noun + " '" + id + "' ";
  throw Error(Error::Kind::forbidden, param,
              owner.empty()
                  ? what +
                        "has no owner (it was made before owners were recorded, or by the command "
                        "line); only an admin may " +
                        verb + " it"
                  : what + "belongs to '" + owner + "'; only its owner or an admin may " + verb + " it");
}

}  // namespace trailscope::server
