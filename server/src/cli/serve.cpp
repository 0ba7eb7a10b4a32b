#include <iostream>
#include <thread>

#include "trailscope/core/json_text.hpp"
#include "cli/commands.hpp"
#include "cli/demo_dataset.hpp"
#include "net/http_server.hpp"
#include "net/ws_hub.hpp"
#include "store/clickhouse_store.hpp"
#include "store/embedded_store.hpp"
#include "trailscope/core/backend.hpp"
#include "limits.hpp"
#include "trailscope/ocl_info.hpp"

namespace trailscope::cli {
namespace fs = std::filesystem;
using namespace trailscope::server;

void add_serve(CLI::App& app) {
  auto* cmd = app.add_subcommand("serve", "Run the HTTP/WebSocket service and the browser app");
  struct Opts {
    std::string data_dir = default_data_dir(), host = "127.0.0.1", web_root = "web/dist", demo_source;
    unsigned short port = 8080;
    unsigned threads = 2;
    bool demo = false, public_reads = false;
    std::size_t demo_flights = 20000;
    std::string backend;
    std::string store;
  };
  auto o = std::make_shared<Opts>();
  cmd->add_option("--data-dir", o->data_dir, "store folder (created if absent)")->capture_default_str();
  cmd->add_option("--host", o->host, "address to listen on")->capture_default_str();
  cmd->add_option("--port", o->port, "port to listen on (0 = any free port)")->capture_default_str();
  cmd->add_option("--threads", o->threads, "I/O threads")->capture_default_str()->check(CLI::Range(1u, 64u));
  // Browser-side safety (net/origin_policy.hpp): the names the server answers to, the origins allowed.
  auto names = std::make_shared<std::vector<std::string>>(),
       origins = std::make_shared<std::vector<std::string>>();
  cmd->add_option(
      "--server-name", *names,
      "a name the server answers to (Host), 'name' or 'name:port'; repeatable (default: the listen "
      "address, localhost, 127.0.0.1 and [::1] with the port)");
  cmd->add_option("--allow-origin", *origins,
                  "an origin (scheme://host[:port]) whose pages may send state-changing requests and open "
                  "WebSockets besides the server's own; repeatable");
  cmd->add_option("--web-root", o->web_root, "folder of the built browser app (web/dist)")
      ->capture_default_str();
  cmd->add_option("--backend", o->backend, "compute backend: cpu | opencl | auto");
  cmd->add_option("--store", o->store,
                  "where datasets live: 'embedded' (the data folder, default) or "
                  "clickhouse://HOST:PORT[,HOST:PORT...]/DB?cluster=NAME (a ClickHouse cluster; the data "
                  "folder keeps everything else)");
  cmd->add_flag("--demo", o->demo, "create the generated demo dataset 'demo' first if it is absent");
  cmd->add_flag("--public-reads", o->public_reads,
                "serve GET and HEAD of every read-only route without a token (writes still need one)");
  cmd->add_option("--demo-flights", o->demo_flights, "flights in the demo dataset")->capture_default_str();
  cmd->add_option("--demo-source", o->demo_source,
                  "folder with vega-datasets' airports.csv and flights-airport.csv (default: "
                  "web/node_modules/vega-datasets/data)");
  cmd->callback([o, names, origins] {
    if (!o->backend.empty()) set_default_backend(parse_backend(o->backend, "--backend"));
    // Compile the kernels now rather than on the first tile (about 1 s with a cold PoCL cache), where
    // tiles can run on OpenCL: always when asked for, and under `auto` on a GPU.
    if (default_backend() == Backend::opencl ||
        (default_backend() == Backend::auto_ && opencl_info().device_type == "gpu"))
      std::thread([] { opencl_warm_up(); }).detach();
    // The data folder holds uploads, tokens and every other store whatever backend holds the datasets.
    auto embedded = std::make_shared<EmbeddedStore>(o->data_dir, EmbeddedStore::Leftovers::remove);
    std::shared_ptr<DatasetStore> store = embedded;
    if (!o->store.empty() && o->store != "embedded") {
      store = open_dataset_store(o->store, o->data_dir, EmbeddedStore::Leftovers::remove);
      std::cout << "datasets in " << o->store << std::endl;
    }
    store->list();  // load every dataset now, so that no first request pays for reading one
    if (o->demo && !store->contains("demo"))
      create_demo_dataset(*store, "demo", o->demo_flights, 42, o->demo_source);
    std::error_code ec;
    fs::path web = o->web_root;
    if (!fs::exists(web / "index.html", ec)) {
      std::cerr << "note: no browser app at " << web << " (build it with `make web`); serving the API only\n";
      web.clear();
    }
    // The hub outlives the app: jobs still finishing while the app shuts down announce their end to it.
    WsHub hub;
    App app(store, embedded->upload_dir(), web, limits::kTileCacheBytes, embedded->root());
    app.jobs.add_listener([&hub](const JobState& s) {
      hub.broadcast(json_text({{"type", "job"}, {"job", s.to_json()}}));
    });
    app.access->set_public_reads(o->public_reads);
    // Access control is on from the first start: with no token yet, the first admin's is made and shown once.
    if (app.access->tokens().empty()) {
      const IssuedToken first = app.access->tokens().create("admin", Role::admin);
      std::cout << "first admin token (shown once, store it): " << first.token << std::endl;
    }
    const Router router = make_router(app);
    ServerOptions so{o->host, o->port, o->threads, *names, *origins};
    if (o->demo) create_demo_videos(*app.videos);
    run_http_server(
        so, router, hub, embedded->upload_dir(),
        [&](unsigned short port) {
          std::cout << "trailscope " TRAILSCOPE_VERSION " serving " << store->list().size()
                    << " dataset(s) at http://" << o->host << ":" << port << "/" << std::endl;
          // As Jupyter does: a URL that signs the local user in once (an admin session in this browser).
          const std::string host = o->host == "0.0.0.0" || o->host == "::" ? "127.0.0.1" : o->host;
          std::cout << "sign in (once, within " << limits::kLoginCodeSeconds / 60 << " min): http://"
                    << (host.find(':') != std::string::npos ? "[" + host + "]" : host) << ":" << port
                    << "/?login=" << app.access->issue_login_code() << std::endl;
        },
        app.replays.get(), app.bundle_streams.get());
    std::cout << "stopped" << std::endl;
  });
}

}  // namespace trailscope::cli
