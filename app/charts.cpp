#include "app/charts.h"

#include "app/process.h"
#include "render/atomic_file.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <sstream>

namespace brume::app {
namespace {

namespace fs = std::filesystem;

// Exact methods reach float rounding (~1e-8); a log axis needs a floor to draw them.
constexpr double kErrorFloor = 1e-9;

std::string quoted(const std::string& s) {
    std::string out = "\"";
    for (char c : s) out += (c == '"' || c == '\\') ? std::string("\\") + c : std::string(1, c);
    return out + "\"";
}

std::string num(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", std::max(v, kErrorFloor));
    return text;
}

// The script draws once to SVG and once to PNG, so both files always show the same chart.
std::string both_terminals(const std::string& stem, const std::string& body) {
    return "set terminal svg size 900,600 dynamic background rgb 'white' font 'Sans,12'\n"
           "set output " + quoted(stem + ".svg") + "\n" + body +
           "set terminal pngcairo size 900,600 font 'Sans,10'\n"
           "set output " + quoted(stem + ".png") + "\n" + "replot\n";
}

}  // namespace

std::vector<ChartPoint> pareto_front(std::vector<ChartPoint> points) {
    std::sort(points.begin(), points.end(), [](const ChartPoint& a, const ChartPoint& b) {
        return a.ms < b.ms || (a.ms == b.ms && a.error < b.error);
    });
    std::vector<ChartPoint> front;
    double best = INFINITY;
    for (const ChartPoint& p : points)
        if (p.error < best) {
            front.push_back(p);
            best = p.error;
        }
    return front;
}

std::vector<ChartLabel> chart_labels(const std::vector<ChartPoint>& points) {
    std::vector<ChartLabel> labels;
    // Ratios, as the chart's log axes show them; exact methods' errors at the axis' floor.
    const auto near = [](double a, double b, double ratio) {
        const double lo = std::min(a, b), hi = std::max(a, b);
        return hi <= lo * ratio;
    };
    for (const ChartPoint& p : points) {
        const double error = std::max(p.error, kErrorFloor);
        auto it = std::find_if(labels.begin(), labels.end(), [&](const ChartLabel& l) {
            return near(l.ms, p.ms, kLabelMergeTime) && near(l.error, error, kLabelMergeError);
        });
        if (it == labels.end())
            labels.push_back({p.ms, error, p.method});
        else
            it->text += ", " + p.method;
    }
    return labels;
}

ChartsWritten write_charts(const fs::path& dir, const std::vector<ChartPoint>& points,
                           const std::vector<TemporalSeries>& temporal, const std::vector<DepthErrorSeries>& all_depth) {
    std::vector<std::pair<std::string, std::string>> scripts;  // stem, gnuplot script

    // Speed against accuracy, with the Pareto front.
    {
        std::ostringstream data, front;
        data << "# method ms rmse_over_peak exact\n";
        for (const ChartPoint& p : points) data << quoted(p.method) << ' ' << num(p.ms) << ' ' << num(p.error) << ' ' << p.exact << '\n';
        for (const ChartPoint& p : pareto_front(points)) front << num(p.ms) << ' ' << num(p.error) << '\n';
        std::ostringstream labels;
        labels << "# ms rmse_over_peak label (methods drawn on one spot share it)\n";
        for (const ChartLabel& l : chart_labels(points)) labels << num(l.ms) << ' ' << num(l.error) << ' ' << quoted(l.text) << '\n';
        write_file_atomically(dir / "speed_accuracy.dat", data.str());
        write_file_atomically(dir / "pareto_front.dat", front.str());
        write_file_atomically(dir / "speed_accuracy_labels.dat", labels.str());
        scripts.push_back({"speed_accuracy",
                           both_terminals("speed_accuracy",
                                          "set title 'Speed against accuracy (mean over scenes; lower left is better)'\n"
                                          "set xlabel 'median frame time, ms (geometric mean over scenes)'\n"
                                          "set ylabel 'RMSE / peak against the reference'\n"
                                          "set logscale xy\nset grid\nset key outside bottom center horizontal\n"
                                          "set format y '%.0e'\n"
                                          "plot 'pareto_front.dat' using 1:2 with lines lw 2 lc rgb '#888888' title 'Pareto front', \\\n"
                                          "     'speed_accuracy.dat' using 2:3 with points pt 7 ps 1.5 title 'methods', \\\n"
                                          "     'speed_accuracy_labels.dat' using 1:2:3 with labels offset 1,0.7 left notitle\n")});
    }

    // Temporal (popping) error over time, one chart per animated scene.
    std::set<std::string> scenes;
    for (const TemporalSeries& s : temporal) scenes.insert(s.scene);
    for (const std::string& scene : scenes) {
        std::ostringstream data, plot;
        int block = 0;
        plot << "set title " << quoted("Temporal error per frame step: " + scene + " (spikes are pops)") << "\n"
             << "set xlabel 'frame step'\nset ylabel 'mean |(I_t - I_{t-1}) - (R_t - R_{t-1})| / peak'\n"
             << "set logscale y\nset format y '%.0e'\nset grid\nset key outside right\nplot ";
        for (const TemporalSeries& s : temporal) {
            if (s.scene != scene) continue;
            data << "# " << s.method << "\n";
            for (std::size_t t = 0; t < s.error.size(); ++t) data << t + 1 << ' ' << num(s.error[t]) << '\n';
            data << "\n\n";
            plot << (block ? ", \\\n     " : "") << "'temporal_" << scene << ".dat' index " << block
                 << " using 1:2 with linespoints title " << quoted(s.method);
            ++block;
        }
        plot << "\n";
        write_file_atomically(dir / ("temporal_" + scene + ".dat"), data.str());
        scripts.push_back({"temporal_" + scene, both_terminals("temporal_" + scene, plot.str())});
    }

    // Error against depth complexity, of the series that have points.
    std::vector<DepthErrorSeries> depth;
    for (const DepthErrorSeries& d : all_depth)
        if (!d.points.empty()) depth.push_back(d);
    if (!depth.empty()) {
        std::ostringstream data, plot;
        plot << "set title 'Error against depth complexity (static scenes)'\n"
             << "set xlabel 'spheres along the pixel ray (list length)'\nset ylabel 'mean |error| / peak'\n"
             << "set logscale y\nset format y '%.0e'\nset grid\nset key outside right\nplot ";
        for (std::size_t k = 0; k < depth.size(); ++k) {
            data << "# " << depth[k].method << "\n";
            for (const auto& [n, e] : depth[k].points) data << n << ' ' << num(e) << '\n';
            data << "\n\n";
            plot << (k ? ", \\\n     " : "") << "'error_vs_depth.dat' index " << k << " using 1:2 with linespoints title "
                 << quoted(depth[k].method);
        }
        plot << "\n";
        write_file_atomically(dir / "error_vs_depth.dat", data.str());
        scripts.push_back({"error_vs_depth", both_terminals("error_vs_depth", plot.str())});
    }

    ChartsWritten written;
    for (const auto& [stem, script] : scripts) written.stems.push_back(stem);
    written.drawn = draw_charts(dir, scripts);
    return written;
}

std::vector<std::string> remove_charts_not_written(const fs::path& dir, const std::vector<std::string>& known,
                                                   const std::vector<std::string>& written) {
    std::vector<std::string> removed;
    for (const std::string& stem : known) {
        if (std::find(written.begin(), written.end(), stem) != written.end()) continue;
        std::vector<std::string> names;
        for (const char* ext : {".dat", ".gp", ".svg", ".png", ".gnuplot.log"}) names.push_back(stem + ext);
        if (stem == "speed_accuracy") {
            names.push_back("pareto_front.dat");
            names.push_back("speed_accuracy_labels.dat");
        }
        for (const std::string& name : names) {
            std::error_code ec;
            if (fs::remove(dir / name, ec)) removed.push_back((dir / name).string());
        }
    }
    return removed;
}

namespace {

// Writes each script as DIR/STEM.gp and runs gnuplot on it; returns the SVG and PNG files drawn.
std::vector<std::string> draw_charts_impl(const fs::path& dir,
                                          const std::vector<std::pair<std::string, std::string>>& scripts) {
    std::vector<std::string> written;
    bool gnuplot_missing = false;
    for (const auto& [stem, script] : scripts) {
        const fs::path gp = dir / (stem + ".gp");
        write_file_atomically(gp, script);
        // gnuplot writes the pictures in place: one it could not finish is empty or cut short, and one
        // not drawn this time is an earlier run's beside this run's data. Neither is left.
        const auto remove_pictures = [&] {
            std::error_code ec;
            fs::remove(dir / (stem + ".svg"), ec);
            fs::remove(dir / (stem + ".png"), ec);
        };
        if (gnuplot_missing) {
            remove_pictures();
            continue;
        }
        // gnuplot resolves the data files relative to its working directory: run it in DIR.
        const int status = run_process({"sh", "-c", "cd \"$0\" && exec gnuplot \"$1\"", dir.string(), gp.filename().string()},
                                       (dir / (stem + ".gnuplot.log")).string());
        if (status == 127 || status < 0) {
            gnuplot_missing = true;
            remove_pictures();
            std::fprintf(stderr, "brume: gnuplot is not installed (Debian: gnuplot-nox); the charts' data and scripts "
                                 "are in %s: run gnuplot there on each .gp file\n", dir.c_str());
            continue;
        }
        if (status != 0) {
            remove_pictures();
            std::fprintf(stderr, "brume: gnuplot failed on %s (see %s); %s.svg and %s.png were not drawn\n", gp.c_str(),
                         (dir / (stem + ".gnuplot.log")).c_str(), stem.c_str(), stem.c_str());
            continue;
        }
        std::error_code ec;
        fs::remove(dir / (stem + ".gnuplot.log"), ec);
        written.push_back((dir / (stem + ".svg")).string());
        written.push_back((dir / (stem + ".png")).string());
    }
    return written;
}

}  // namespace

std::vector<std::string> draw_charts(const fs::path& dir, const std::vector<std::pair<std::string, std::string>>& scripts) {
    return draw_charts_impl(dir, scripts);
}

std::vector<std::string> write_vdb_chart(const fs::path& dir, const std::vector<VdbSeries>& series) {
    std::ostringstream data, plot;
    plot << "set title 'OpenVDB import: spheres against measured optical-depth error'\n"
         << "set xlabel 'spheres'\nset ylabel 'RMS optical-depth error (relative)'\n"
         << "set logscale xy\nset format x '10^{%L}'\nset format y '%.0e'\nset grid\nset key top right\nplot ";
    for (std::size_t k = 0; k < series.size(); ++k) {
        data << "# " << series[k].label << "\n";
        for (const auto& [spheres, error] : series[k].points) data << spheres << ' ' << num(error) << '\n';
        data << "\n\n";
        plot << (k ? ", \\\n     " : "") << "'vdb_spheres_vs_error.dat' index " << k
             << " using 1:2 with linespoints title " << quoted(series[k].label);
    }
    plot << "\n";
    write_file_atomically(dir / "vdb_spheres_vs_error.dat", data.str());
    return draw_charts(dir, {{"vdb_spheres_vs_error", both_terminals("vdb_spheres_vs_error", plot.str())}});
}

}  // namespace brume::app
