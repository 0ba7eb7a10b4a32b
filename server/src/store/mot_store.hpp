#pragma once
// MOTChallenge text files (ground truth, tracker results, 3D points; metrics/mot_text.hpp), the inputs of
// POST /api/v1/metrics, persisted as <root>/mot/<id>.txt and <root>/mot/<id>.json, the file's row written
// last (temporary file + rename, as the text before it): a text without its row is an interrupted write
// and is removed at the next start. Rows stay in memory; texts are read on use. At most
// limits::kMaxStoredRuns files are kept; one more is refused (409).
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "store/row_store.hpp"

namespace trailscope::server {

class MotStore {
 public:
  static constexpr const char* kNoun = "MOT file";  ///< in messages
  /// Opens (creating if needed) <root>/mot. A row that fails to load is reported on stderr and skipped.
  explicit MotStore(std::filesystem::path root);

  /// Every file's row, oldest first.
  std::vector<nlohmann::json> list() const;
  /// {id ("m1", ...), name, kind ("gt" | "result" | "points"), created, bytes, rows, frames (last frame
  /// number), ids (distinct object ids), owner}. Throws not_found(param).
  nlohmann::json meta(const std::string& id, const std::string& param = "mot") const;
  /// The whole text. Throws not_found(param).
  std::string text(const std::string& id, const std::string& param = "mot") const;
  /// Checks `text` with the reader of `kind` (every malformed line, Error(unprocessable, "body")) and
  /// stores it under the next id, owned by `owner`. Throws invalid_argument("kind") for another kind,
  /// Error(conflict, "mot") at limits::kMaxStoredRuns. Returns the row.
  nlohmann::json put(const std::string& name, const std::string& kind, const std::string& text,
                     const std::string& owner = "");
  /// Throws not_found("mot").
  void remove(const std::string& id);

 private:
  RowStore rows_;
};

}  // namespace trailscope::server
