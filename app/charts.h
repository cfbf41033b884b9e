// Charts for `brume bench`, drawn by gnuplot (Debian gnuplot-nox) into SVG and PNG. Without gnuplot
// the data files and scripts are still written and the command says how to draw them.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace brume::app {

struct ChartPoint {
    std::string method;
    double ms = 0;     // geometric mean over scenes of the median frame time
    double error = 0;  // mean over scenes of RMSE / peak against the reference
    bool exact = false;
};

struct TemporalSeries {
    std::string scene, method;
    std::vector<double> error;  // per frame step
};

struct DepthErrorSeries {
    std::string method;
    std::vector<std::pair<double, double>> points;  // (list length, mean |error| / peak)
};

// What write_charts made: the stems of the charts whose data and script it wrote ("speed_accuracy",
// "temporal_crossing", ...), and the SVG and PNG files gnuplot drew of them.
struct ChartsWritten {
    std::vector<std::string> stems;
    std::vector<std::string> drawn;
};

// Writes DIR/*.dat, DIR/*.gp and, when gnuplot runs, DIR/*.svg and DIR/*.png. A depth series without
// points is left out, and the depth chart with it when no series has any (gnuplot fails on an empty
// plot, and left a 0-byte SVG).
ChartsWritten write_charts(const std::filesystem::path& dir, const std::vector<ChartPoint>& points,
                           const std::vector<TemporalSeries>& temporal, const std::vector<DepthErrorSeries>& depth);

// The files of chart STEM in a bench's folder: STEM.dat, .gp, .svg, .png and .gnuplot.log (speed_accuracy
// also pareto_front.dat and speed_accuracy_labels.dat). Removes those of each stem of `known` that is not
// in `written`, so that a run into a folder an earlier run filled leaves no chart of that run beside its
// own results (temporal_crossing.svg after a run of static scenes); returns the paths removed. Files of
// other names are never touched.
std::vector<std::string> remove_charts_not_written(const std::filesystem::path& dir, const std::vector<std::string>& known,
                                                   const std::vector<std::string>& written);

// `brume bench vdb`: per grid, (sphere count, RMS optical-depth error) for each tolerance.
struct VdbSeries {
    std::string label;
    std::vector<std::pair<double, double>> points;
};
std::vector<std::string> write_vdb_chart(const std::filesystem::path& dir, const std::vector<VdbSeries>& series);

// Writes each (stem, gnuplot script) as DIR/STEM.gp and draws it; returns the SVG and PNG files drawn.
// Without gnuplot, says so once on stderr and returns none. A chart not drawn (no gnuplot, or gnuplot
// failed: said on stderr) leaves no STEM.svg or STEM.png, neither an empty one nor an earlier run's.
std::vector<std::string> draw_charts(const std::filesystem::path& dir,
                                     const std::vector<std::pair<std::string, std::string>>& scripts);

// The Pareto front of `points`: those no other point beats on both time and error, by time.
std::vector<ChartPoint> pareto_front(std::vector<ChartPoint> points);

// The speed-against-accuracy chart's labels: points that would be drawn on top of one another (within
// kLabelMergeTime of each other's time and kLabelMergeError of their error, as ratios) share one
// label, "trace, auto", at the first one's place, where two labels were printed over each other.
struct ChartLabel {
    double ms = 0, error = 0;
    std::string text;
};
inline constexpr double kLabelMergeTime = 1.05, kLabelMergeError = 1.12;
std::vector<ChartLabel> chart_labels(const std::vector<ChartPoint>& points);

}  // namespace brume::app
