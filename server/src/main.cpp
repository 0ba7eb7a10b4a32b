// trailscope: the service (`serve`) and a CLI verb for each capability.
#include <iostream>

#include "cli/commands.hpp"
#include "trailscope/core/error.hpp"

int main(int argc, char** argv) {
  CLI::App app{"TrailScope " TRAILSCOPE_VERSION
               ": visual analytics of multidimensional time-dependent trails"};
  app.set_version_flag("--version", TRAILSCOPE_VERSION);
  app.require_subcommand(1);
  trailscope::cli::add_serve(app);
  trailscope::cli::add_ingest(app);
  trailscope::cli::add_query(app);
  trailscope::cli::add_tile(app);
  trailscope::cli::add_demo(app);
  trailscope::cli::add_bundle(app);
  trailscope::cli::add_metrics(app);
  trailscope::cli::add_synth(app);
  trailscope::cli::add_video(app);
  trailscope::cli::add_dmd(app);
  trailscope::cli::add_project(app);
  trailscope::cli::add_track(app);
  trailscope::cli::add_compare(app);
  trailscope::cli::add_congestion(app);
  trailscope::cli::add_token(app);
  trailscope::cli::add_export(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const trailscope::Error& e) {
    std::cerr << "trailscope: " << e.what() << "\n";
    return e.kind() == trailscope::Error::Kind::internal ? 1 : 2;
  } catch (const std::exception& e) {
    std::cerr << "trailscope: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
