#pragma once
// The routes every stored collection shares (graphs, videos, MOT files, runs, bundles, sweeps): GET of the
// collection lists it ({"<key>": [metadata, oldest first]}), GET of an item answers its metadata, DELETE
// removes it (204) when the caller is its owner or an admin (routes/ownership.hpp; 403 otherwise, after the
// 404 of an unknown item). None takes query parameters. Routes that do more (a bundle's delete also drops its
// cached tiles) have handlers of their own.
#include <memory>

#include "routes/app.hpp"
#include "routes/ownership.hpp"

namespace trailscope::server::handlers {

/// A collection of the App: its JSON key, the path parameter naming an item, and what the server lacks
/// when it was started without it (need()).
template <typename Store>
struct Collection {
  std::shared_ptr<Store> App::*part;
  const char* key;      ///< "graphs"
  const char* param;    ///< "graph", as in /api/v1/graphs/{graph}
  const char* missing;  ///< "a graph store"
};

template <typename Store>
Router::Handler list_handler(App& app, Collection<Store> c) {
  return [&app, c](const Request& req, const PathParams&) {
    reject_unknown_params(req, {});
    return Response::json(200, {{c.key, need(app.*c.part, c.missing).list()}});
  };
}

template <typename Store>
Router::Handler get_handler(App& app, Collection<Store> c) {
  return [&app, c](const Request& req, const PathParams& p) {
    reject_unknown_params(req, {});
    return Response::json(200, need(app.*c.part, c.missing).meta(p.at(c.param)));
  };
}

template <typename Store>
Router::Handler delete_handler(App& app, Collection<Store> c) {
  return [&app, c](const Request& req, const PathParams& p) {
    reject_unknown_params(req, {});
    Store& store = need(app.*c.part, c.missing);
    const std::string id = p.at(c.param);
    require_owner(req, c.param, Store::kNoun, id, store.meta(id).value("owner", ""));
    store.remove(id);
    return Response::no_content();
  };
}

}  // namespace trailscope::server::handlers
