// The preview's timeline (app/preview_timeline.h): an edit of one emitter keeps the frames from before
// that emitter's first birth, and the frames after it are exactly those of a timeline built afresh from
// the edited preset, which is what `brume play` renders.
#include "app/preview_timeline.h"
#include "sim/preset_file.h"

#include <gtest/gtest.h>

#include <string>

namespace brume::app {
namespace {

// A steady jet from the start, and a second one that starts 2 s in (1.5 s after the preroll: frame 36).
std::string preset_text(double late_rate, double late_start) {
    return "[preset]\nname = \"late\"\n"
           "[timeline]\nfps = 24.0\nduration = 4.0\npreroll = 0.5\nseed = 5\nresolution = [32, 24]\n"
           "[[emitter]]\ncenter = [0.0, 0.0, 0.0]\nrate = 20.0\ndirection = [1.0, 0.0, 0.0]\nspeed = [1.0, 1.5]\n"
           "lifetime = [2.0, 3.0]\nparticle_radius = [0.1, 0.2]\nextinction = [1.0, 2.0]\n"
           "[[emitter]]\ncenter = [0.0, 1.0, 0.0]\nrate = " + std::to_string(late_rate) +
           "\nstart = " + std::to_string(late_start) +
           "\ndirection = [-1.0, 0.0, 0.0]\nspeed = [1.0, 1.5]\nlifetime = [2.0, 3.0]\nparticle_radius = [0.1, 0.2]\n"
           "extinction = [1.0, 2.0]\n";
}

Preset preset(double late_rate, double late_start) { return parse_preset_toml(preset_text(late_rate, late_start), "late.toml"); }

void expect_same_frame(const PreviewTimeline& a, const PreviewTimeline& b) {
    ASSERT_EQ(a.frame(), b.frame());
    const Scene sa = a.scene(), sb = b.scene();
    ASSERT_EQ(sa.spheres.size(), sb.spheres.size()) << "frame " << a.frame();
    for (std::size_t i = 0; i < sa.spheres.size(); ++i) {
        EXPECT_EQ(sa.spheres[i].center, sb.spheres[i].center) << "sphere " << i << " of frame " << a.frame();
        EXPECT_EQ(sa.spheres[i].radius, sb.spheres[i].radius) << "sphere " << i;
        EXPECT_EQ(sa.spheres[i].extinction, sb.spheres[i].extinction) << "sphere " << i;
        EXPECT_EQ(sa.spheres[i].albedo, sb.spheres[i].albedo) << "sphere " << i;
    }
}

TEST(PreviewTimeline, AnEmitterEditKeepsTheFramesBeforeItsFirstBirth) {
    PreviewTimeline timeline(preset(10.0, 2.0));
    timeline.seek(60);
    const Preset edited = preset(40.0, 2.0);
    const std::optional<int> from = timeline.replace_emitter_keeping_past(edited, 1);
    ASSERT_TRUE(from);
    EXPECT_EQ(*from, 32);  // the last checkpoint (every 8 frames) before frame 36
    EXPECT_EQ(timeline.checkpoints().rbegin()->first, 56);  // taken again on the way back to 60
    PreviewTimeline fresh(edited);
    fresh.seek(60);
    expect_same_frame(timeline, fresh);
    for (const int f : {10, 40, 95}) {  // before, just after the emitter's start, and the end
        timeline.seek(f);
        fresh.seek(f);
        expect_same_frame(timeline, fresh);
    }
    EXPECT_GT(timeline.scene().spheres.size(), PreviewTimeline(preset(10.0, 2.0)).scene().spheres.size());
}

TEST(PreviewTimeline, AnEarlierStartKeepsOnlyWhatCameBeforeIt) {
    PreviewTimeline timeline(preset(10.0, 2.0));
    timeline.seek(80);
    const Preset edited = preset(10.0, 1.0);  // now from frame 12
    const std::optional<int> from = timeline.replace_emitter_keeping_past(edited, 1);
    ASSERT_TRUE(from);
    EXPECT_EQ(*from, 8);
    PreviewTimeline fresh(edited);
    fresh.seek(80);
    expect_same_frame(timeline, fresh);
}

TEST(PreviewTimeline, AnEmitterThatHasEmittedSinceFrameZeroCannotKeepThePast) {
    PreviewTimeline timeline(preset(10.0, 2.0));
    timeline.seek(30);
    Preset edited = preset(10.0, 2.0);
    edited.emitters[0].rate = 30.0;  // the first jet emits from the preroll on
    EXPECT_FALSE(timeline.replace_emitter_keeping_past(edited, 0));
    EXPECT_EQ(timeline.frame(), 30);  // nothing changed
    EXPECT_FALSE(timeline.replace_emitter_keeping_past(preset(10.0, 0.2), 1));  // starts within the preroll
    EXPECT_FALSE(timeline.replace_emitter_keeping_past(edited, 7));             // no such emitter
}

}  // namespace
}  // namespace brume::app
