// The speed-against-accuracy chart's labels (app/charts.h): points drawn on one spot share a label,
// points apart keep their own, and the Pareto front keeps the points no other beats. The charts' files:
// none is left empty or from an earlier run beside a new run's results.
#include "app/charts.h"
#include "tests/scratch_dir.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace brume::app {
namespace {

TEST(ChartLabels, PointsOnOneSpotShareALabelAtTheFirstOnesPlace) {
    // As `brume bench` measured them: trace and auto 3% apart with the same error, ppll and
    // ppll-general 4% apart, sorted far from both.
    const std::vector<ChartPoint> points{{"ppll", 6.56, 4.8e-7, true},   {"trace", 2.09, 2.3e-7, true},
                                         {"sorted", 3.9, 1.1e-2, false}, {"ppll-general", 6.8, 4.8e-7, true},
                                         {"auto", 2.16, 2.3e-7, true}};
    const std::vector<ChartLabel> labels = chart_labels(points);
    ASSERT_EQ(labels.size(), 3u);
    EXPECT_EQ(labels[0].text, "ppll, ppll-general");
    EXPECT_EQ(labels[0].ms, 6.56);
    EXPECT_EQ(labels[1].text, "trace, auto");
    EXPECT_EQ(labels[1].ms, 2.09);
    EXPECT_EQ(labels[1].error, 2.3e-7);
    EXPECT_EQ(labels[2].text, "sorted");
}

TEST(ChartLabels, PointsApartInTimeOrInErrorKeepTheirOwn) {
    // 10% apart in time with the same error; the same time with errors 1.5x apart; exact methods whose
    // errors fall below the axis' floor are drawn on it, and so share a label when their times agree.
    const std::vector<ChartPoint> points{{"a", 10.0, 1e-2, false}, {"b", 11.0, 1e-2, false}, {"c", 10.0, 1.5e-2, false},
                                         {"d", 50.0, 0.0, true},   {"e", 51.0, 1e-12, true}};
    const std::vector<ChartLabel> labels = chart_labels(points);
    ASSERT_EQ(labels.size(), 4u);
    EXPECT_EQ(labels[0].text, "a");
    EXPECT_EQ(labels[1].text, "b");
    EXPECT_EQ(labels[2].text, "c");
    EXPECT_EQ(labels[3].text, "d, e");
    EXPECT_GT(labels[3].error, 0.0) << "a log axis cannot draw 0";
}

TEST(ChartLabels, TheParetoFrontKeepsThePointsNoOtherBeats) {
    const std::vector<ChartPoint> points{{"slow exact", 6.0, 5e-7, true}, {"fast exact", 2.0, 2e-7, true},
                                         {"approximate", 4.0, 1e-2, false}};
    const std::vector<ChartPoint> front = pareto_front(points);
    ASSERT_EQ(front.size(), 1u);
    EXPECT_EQ(front[0].method, "fast exact");
    const std::vector<ChartPoint> traded = pareto_front({{"exact", 6.0, 5e-7, true}, {"cheap", 2.0, 1e-2, false}});
    ASSERT_EQ(traded.size(), 2u);
    EXPECT_EQ(traded[0].method, "cheap");
    EXPECT_EQ(traded[1].method, "exact");
}

namespace fs = std::filesystem;

class ChartFiles : public testing::ScratchDir {
protected:
    void put(const std::string& name, const std::string& text = "an earlier run's\n") const {
        std::ofstream(dir_ / name, std::ios::binary) << text;
    }
    bool has(const std::string& name) const { return fs::exists(dir_ / name); }
};

// bench methods into the folder of an earlier run: that run's charts which this one did not make are
// removed (temporal_crossing.svg after a static-only run), the ones it made and every other file kept.
TEST_F(ChartFiles, ChartsOfAnEarlierRunThatThisOneDidNotMakeAreRemoved) {
    for (const char* ext : {".dat", ".gp", ".svg", ".png", ".gnuplot.log"}) put(std::string("temporal_crossing") + ext);
    put("error_vs_depth.svg");
    put("speed_accuracy.svg");
    put("pareto_front.dat");
    put("results.csv");
    put("temporal_notes.txt");  // not a chart's file: never touched
    const std::vector<std::string> removed =
        remove_charts_not_written(dir_, {"speed_accuracy", "error_vs_depth", "temporal_crossing", "temporal_plume"},
                                  {"speed_accuracy"});
    EXPECT_EQ(removed.size(), 6u);
    for (const char* gone : {"temporal_crossing.dat", "temporal_crossing.gp", "temporal_crossing.svg",
                             "temporal_crossing.png", "temporal_crossing.gnuplot.log", "error_vs_depth.svg"}) {
        EXPECT_FALSE(has(gone)) << gone;
        EXPECT_NE(std::find(removed.begin(), removed.end(), (dir_ / gone).string()), removed.end()) << gone;
    }
    for (const char* kept : {"speed_accuracy.svg", "pareto_front.dat", "results.csv", "temporal_notes.txt"})
        EXPECT_TRUE(has(kept)) << kept;
}

// gnuplot writes a picture in place: one it fails on was left at 0 bytes with exit 0. A chart not drawn
// leaves no picture, neither an empty one nor the earlier run's (with or without gnuplot installed).
TEST_F(ChartFiles, AChartThatIsNotDrawnLeavesNoPicture) {
    put("broken.svg");
    put("broken.png");
    const std::vector<std::string> drawn =
        draw_charts(dir_, {{"broken", "set terminal svg\nset output 'broken.svg'\nplot 'no_such.dat' using 1:2\n"}});
    EXPECT_TRUE(drawn.empty());
    EXPECT_FALSE(has("broken.svg"));
    EXPECT_FALSE(has("broken.png"));
    EXPECT_TRUE(has("broken.gp"));
}

// bench methods --size 2x2: no depth bin had points, gnuplot failed on the empty plot and left a 0-byte
// error_vs_depth.svg. Series without points are left out, and the chart when none has any.
TEST_F(ChartFiles, ADepthChartWithoutPointsIsNotWritten) {
    const ChartsWritten written = write_charts(dir_, {{"trace", 2.0, 1e-7, true}}, {}, {{"trace", {}}, {"sorted", {}}});
    EXPECT_EQ(written.stems, std::vector<std::string>{"speed_accuracy"});
    for (const char* ext : {".dat", ".gp", ".svg", ".png"}) EXPECT_FALSE(has(std::string("error_vs_depth") + ext)) << ext;
    // With one series that has points, the chart holds that one alone.
    const ChartsWritten one =
        write_charts(dir_, {{"trace", 2.0, 1e-7, true}}, {}, {{"trace", {{1.0, 1e-7}, {2.0, 2e-7}}}, {"sorted", {}}});
    EXPECT_EQ(one.stems, (std::vector<std::string>{"speed_accuracy", "error_vs_depth"}));
    std::ifstream data(dir_ / "error_vs_depth.dat");
    const std::string text((std::istreambuf_iterator<char>(data)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("# trace"), std::string::npos) << text;
    EXPECT_EQ(text.find("# sorted"), std::string::npos) << text;
    for (const std::string& file : one.drawn) EXPECT_GT(fs::file_size(file), 0u) << file;
}

}  // namespace
}  // namespace brume::app
