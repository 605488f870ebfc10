#pragma once
/// @file
/// JSON of the bridge's API: the current state (`GET /api/state`, each server-sent event) and
/// the time series (`GET /api/history`, columnar so that a chart takes it as it is).
/// Numbers that are not finite (no estimate yet) are null.

#include <deque>
#include <nlohmann/json.hpp>

#include "retreat/telemetry/aggregator.hpp"

namespace retreat::bridge {

/// {"run": {...}, "telemetry": {...}|null, "poses": {...}|null, "agents": [...],
///  "estimates": {...}, "history": {...}, "samples": {...}, "runs": n, "version": n}
nlohmann::json state_json(const telemetry::Snapshot& snapshot);

/// {"spacing": s, "compactions": n, "points": n, "time": [...], "inside": [...], ...}: one array
/// per HistoryPoint field, oldest first.
nlohmann::json history_json(const std::deque<telemetry::HistoryPoint>& history, double spacing,
                            std::uint64_t compactions);

/// One history point as an object (the same keys as history_json's arrays).
nlohmann::json point_json(const telemetry::HistoryPoint& point);

}  // namespace retreat::bridge
