// Where a finished frame goes when it is not read back: a presenter draws the HDR target (sampled,
// in SHADER_READ_ONLY_OPTIMAL layout) into a window's swapchain image, or into any other target.
// The frame path hands it the frame's command buffer slot once the method's passes are done; what
// the presenter submits may still be running when the next frame is recorded.
#pragma once

#include "render/frame/frame_resources.h"
#include "render/vk/frame_ring.h"

namespace brume {

class Presenter {
public:
    virtual ~Presenter() = default;
    // Records and submits, through `ring` (its current slot is begun and free), the passes that
    // carry `frame`'s HDR target to the screen. Returns false when nothing was shown (a minimised
    // window, an out-of-date swapchain that is recreated for the next frame).
    virtual bool present(const FrameResources& frame, vk::FrameRing& ring) = 0;
};

}  // namespace brume
