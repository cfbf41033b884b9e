// The preview's render thread (app/preview_renderer.h): the newest view wins over views that came in
// while a frame rendered, jobs (screenshots) are never dropped, a frame is the frame path's frame bit
// for bit, and a method the caller drops while its frame renders stays alive until it is done. The
// window side (presents and polls during a slow frame): tests/preview_checks.sh.
#include "gpu_test_env.h"
#include "test_scenes.h"
#include "app/preview_renderer.h"
#include "render/frame/frame_path.h"
#include "render/methods/registry.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <thread>

namespace brume::app {
namespace {

using brume::testing::GpuTest;
using brume::testing::same_bits;
using Clock = std::chrono::steady_clock;

class PreviewRendererTest : public GpuTest {};

// The view of frame `tag`: the overlapping scene seen from a little further each frame, so that
// frames differ.
FrameRequest view(const std::shared_ptr<Method>& method, int tag) {
    FrameRequest r;
    r.scene = brume::testing::overlapping_scene(48, 36);
    r.scene.camera.position.z += 0.1 * tag;
    r.method = method;
    r.frame = tag;
    return r;
}

// Waits (up to 30 s) until the renderer has rendered `frames` frames and has nothing left.
bool settle(const PreviewRenderer& renderer, std::uint64_t frames) {
    const auto until = Clock::now() + std::chrono::seconds(30);
    while (Clock::now() < until) {
        if (renderer.frames_rendered() >= frames && !renderer.busy()) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return false;
}

// While a (slowed) frame renders, two more views come in: the first of them is dropped, the newest
// is rendered next, and it is the frame path's frame of that view bit for bit.
TEST_F(PreviewRendererTest, TheNewestViewWinsOverViewsThatCameInMeanwhile) {
    ::setenv("BRUME_PREVIEW_SLOW_FRAME_MS", "300", 1);  // the test hook: each view takes 300 ms more
    std::atomic<int> wakes = 0;
    PreviewRenderer renderer(device(), [&] { ++wakes; });
    ::unsetenv("BRUME_PREVIEW_SLOW_FRAME_MS");
    const std::shared_ptr<Method> method = make_method(&device(), "soft");
    const std::uint64_t first = renderer.request_view(view(method, 1));
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // the first view is being rendered
    ASSERT_TRUE(renderer.busy());
    renderer.request_view(view(method, 2));
    const std::uint64_t newest = renderer.request_view(view(method, 3));
    EXPECT_GT(newest, first);
    ASSERT_TRUE(settle(renderer, 2));
    EXPECT_EQ(renderer.frames_rendered(), 2u) << "the view between the first and the newest was rendered";
    EXPECT_EQ(wakes.load(), 2);
    std::optional<RenderedFrame> done = renderer.take_view();
    ASSERT_TRUE(done);
    EXPECT_TRUE(done->error.empty()) << done->error;
    EXPECT_EQ(done->id, newest);
    EXPECT_EQ(done->frame, 3);
    EXPECT_FALSE(renderer.take_view()) << "a view is handed over once";
    FramePath path(device());
    EXPECT_TRUE(same_bits(done->image, path.render(*make_method(&device(), "soft")->gpu(), view(method, 3).scene)));
}

// Jobs are rendered in order before a waiting view, and each is kept until it is taken.
TEST_F(PreviewRendererTest, JobsAreNeverDropped) {
    PreviewRenderer renderer(device(), [] {});
    const std::shared_ptr<Method> method = make_method(&device(), "soft");
    const std::uint64_t a = renderer.request_job(view(method, 4));
    const std::uint64_t b = renderer.request_job(view(method, 5));
    renderer.request_view(view(method, 6));
    ASSERT_TRUE(settle(renderer, 3));
    std::optional<RenderedFrame> second = renderer.take_job(b);
    std::optional<RenderedFrame> first = renderer.take_job(a);
    ASSERT_TRUE(first && second);
    EXPECT_EQ(first->frame, 4);
    EXPECT_EQ(second->frame, 5);
    EXPECT_FALSE(same_bits(first->image, second->image));
    EXPECT_FALSE(renderer.take_job(a)) << "a job is handed over once";
    std::optional<RenderedFrame> v = renderer.take_view();
    ASSERT_TRUE(v);
    EXPECT_EQ(v->frame, 6);
}

// The session drops a method (a method switch) while a frame renders with it: the frame holds it,
// and it goes once the frame is done, with nothing of it on the GPU (the validation layer, in
// TearDown, would say otherwise).
TEST_F(PreviewRendererTest, AMethodDroppedWhileItsFrameRendersLivesUntilTheFrameIsDone) {
    PreviewRenderer renderer(device(), [] {});
    std::shared_ptr<Method> method = make_method(&device(), "ppll");
    const std::weak_ptr<Method> watch = method;
    renderer.request_view(view(method, 7));
    method.reset();
    ASSERT_TRUE(settle(renderer, 1));
    std::optional<RenderedFrame> done = renderer.take_view();
    ASSERT_TRUE(done);
    EXPECT_TRUE(done->error.empty()) << done->error;
    EXPECT_TRUE(watch.expired());
}

}  // namespace
}  // namespace brume::app
