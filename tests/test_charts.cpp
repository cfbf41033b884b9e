// The speed-against-accuracy chart's labels (app/charts.h): points drawn on one spot share a label,
// points apart keep their own, and the Pareto front keeps the points no other beats.
#include "app/charts.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace brume::app
