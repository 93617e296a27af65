#include "granular/accuracy/report_io.hpp"

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <ctime>
#include <fstream>
#include <sstream>
#include <thread>
#include <utility>

namespace granular::accuracy {

namespace {

/// JSON has no NaN or infinity: those become null.
nlohmann::json number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

std::string csv_field(const std::string& s) {
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

std::string format(const char* fmt, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}

/// A calibration's fields and its one-line description.
nlohmann::json calibration_json(const Calibration& cal) {
  return {{"cell_m", cal.cell_m},
          {"tick_s", cal.tick_s()},
          {"gravity", cal.gravity},
          {"calibration_cells", cal.calibration_cells},
          {"bulk_density", cal.bulk_density},
          {"description", cal.describe()}};
}

}  // namespace

std::string report_text(const SuiteReport& report) {
  std::ostringstream out;
  const SuiteConfig& c = report.config;
  out << "configuration  rules " << c.rules << ", backend " << c.backend_description << ", size " << c.size << ", " << c.stepping << " stepping, seed " << c.seed
      << "\n";
  out << "calibration    " << c.calibration.describe() << "\n";
  for (const TestReport& t : report.tests) {
    out << "\n== " << t.test << ": " << t.title << "\n";
    out << "   scene: " << t.scene << "\n";
    out << "   run time " << format("%.2f", t.seconds) << " s, " << t.ticks << " ticks, "
        << format("%.3g", t.cell_updates) << " cell-updates; grains conserved: " << (t.conserved ? "yes" : "NO") << "\n";
    char head[200];
    std::snprintf(head, sizeof head, "   %-30s %12s %12s %12s %10s  %s\n", "metric", "measured", "reference", "error",
                  "target", "met");
    out << head;
    for (const Metric& m : t.metrics) {
      char row[300];
      std::snprintf(row, sizeof row, "   %-30s %12.4g %12.4g %+12.4g %10s  %s\n", (m.name + (m.unit.empty() ? "" : " (" + m.unit + ")")).c_str(),
                    m.measured, m.reference, m.error(), ("+-" + format("%.3g", m.tolerance)).c_str(), m.met() ? "yes" : "NO");
      out << row;
      out << "      reference: " << m.source << "\n";
    }
    for (const std::string& n : t.notes) out << "   note: " << n << "\n";
  }
  out << "\nsuite          " << format("%.2f", report.seconds()) << " s, mean normalized error "
      << format("%.3f", report.mean_normalized_error()) << " (|error| / target; < 1 meets it), grains conserved "
      << (report.conserved() ? "yes" : "NO") << "\n";
  return out.str();
}

RunInfo current_run_info(std::string command) {
  RunInfo info;
  info.command = std::move(command);
  const std::time_t now = std::time(nullptr);
  char date[32];
  std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  info.date = date;
  std::string model = "unknown CPU";
  std::ifstream cpuinfo("/proc/cpuinfo");
  for (std::string line; std::getline(cpuinfo, line);)
    if (line.rfind("model name", 0) == 0 && line.find(':') != std::string::npos) {
      model = line.substr(line.find(':') + 2);
      break;
    }
  info.machine = model + ", " + std::to_string(std::thread::hardware_concurrency()) + " hardware threads";
  return info;
}

std::string report_json(const std::vector<SuiteReport>& reports, const Calibration& cal, const RunInfo& info) {
  nlohmann::json j;
  j["command"] = info.command;
  j["date"] = info.date;
  j["machine"] = info.machine;
  j["calibration"] = calibration_json(cal);
  j["configurations"] = nlohmann::json::array();
  for (const SuiteReport& r : reports) {
    nlohmann::json cj;
    cj["config"] = {{"rules", r.config.rules},
                    {"backend", r.config.backend},
                    {"backend_description", r.config.backend_description},
                    {"size", r.config.size},
                    {"stepping", r.config.stepping},
                    {"threads", r.config.threads},
                    {"seed", r.config.seed}};
    cj["calibration"] = calibration_json(r.config.calibration);
    cj["seconds"] = r.seconds();
    cj["mean_normalized_error"] = number(r.mean_normalized_error());
    cj["conserved"] = r.conserved();
    cj["tests"] = nlohmann::json::array();
    for (const TestReport& t : r.tests) {
      nlohmann::json tj;
      tj["test"] = t.test;
      tj["title"] = t.title;
      tj["scene"] = t.scene;
      tj["seconds"] = t.seconds;
      tj["ticks"] = t.ticks;
      tj["cell_updates"] = t.cell_updates;
      tj["conserved"] = t.conserved;
      tj["mean_normalized_error"] = number(t.mean_normalized_error());
      tj["notes"] = t.notes;
      tj["metrics"] = nlohmann::json::array();
      for (const Metric& m : t.metrics)
        tj["metrics"].push_back({{"name", m.name},
                                 {"unit", m.unit},
                                 {"measured", number(m.measured)},
                                 {"reference", m.reference},
                                 {"tolerance", m.tolerance},
                                 {"error", number(m.error())},
                                 {"normalized_error", number(m.normalized_error())},
                                 {"met", m.met()},
                                 {"source", m.source}});
      tj["series"] = nlohmann::json::array();
      for (const Series& s : t.series) {
        nlohmann::json xs = nlohmann::json::array(), ys = nlohmann::json::array();
        for (double v : s.x) xs.push_back(number(v));
        for (double v : s.y) ys.push_back(number(v));
        tj["series"].push_back(
            {{"name", s.name}, {"x_label", s.x_label}, {"y_label", s.y_label}, {"x", xs}, {"y", ys}, {"reference", s.reference}});
      }
      cj["tests"].push_back(tj);
    }
    j["configurations"].push_back(cj);
  }
  // Invalid UTF-8 (in a CPU or GPU name) is written as U+FFFD, as the CLI's json_text does.
  return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

std::string report_csv(const std::vector<SuiteReport>& reports) {
  std::ostringstream out;
  out << "rules,backend,size,stepping,test,metric,unit,measured,reference,tolerance,error,normalized_error,met,seconds,ticks,"
         "conserved,source\n";
  for (const SuiteReport& r : reports)
    for (const TestReport& t : r.tests)
      for (const Metric& m : t.metrics)
        out << r.config.rules << ',' << r.config.backend << ',' << r.config.size << ',' << r.config.stepping << ',' << t.test << ',' << m.name << ','
            << m.unit << ',' << format("%.6g", m.measured) << ',' << format("%.6g", m.reference) << ','
            << format("%.6g", m.tolerance) << ',' << format("%.6g", m.error()) << ','
            << format("%.6g", m.normalized_error()) << ',' << (m.met() ? "yes" : "no") << ','
            << format("%.4f", t.seconds) << ',' << t.ticks << ',' << (t.conserved ? "yes" : "no") << ','
            << csv_field(m.source) << '\n';
  return out.str();
}

}  // namespace granular::accuracy
