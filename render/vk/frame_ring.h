// Frames in flight: a ring of slots, each with its own command pool, command buffer, fence and the
// two semaphores a presented frame needs. The frame path records every submission into a slot;
// recording into a slot first waits for that slot's previous submission, so a frame can still be on
// its way to the screen while the next one is recorded.
#pragma once

#include "render/vk/device.h"
#include "render/vk/handle.h"

#include <cstdint>
#include <vector>

namespace brume::vk {

struct FrameSlot {
    UniqueCommandPool pool;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    UniqueFence done;                // signalled when the slot's last submission completes
    UniqueSemaphore image_acquired;  // a presenter's acquire signals it, the frame's submission waits
    UniqueSemaphore ready_to_present;  // the frame's submission signals it, the present waits
    bool pending = false;            // submitted and not yet waited for
};

class FrameRing {
public:
    static constexpr std::uint32_t kDefaultSlots = 2;

    FrameRing(const Device& device, std::uint32_t slots = kDefaultSlots);
    ~FrameRing();
    FrameRing(const FrameRing&) = delete;
    FrameRing& operator=(const FrameRing&) = delete;

    // Moves to the next slot, waits for its previous submission and begins its command buffer.
    FrameSlot& begin_next();
    // Begins the current slot's command buffer again (after wait()), for a frame's next step.
    FrameSlot& begin_again();
    // Ends and submits the current slot's commands, optionally waiting on and signalling semaphores.
    void submit(VkSemaphore wait = VK_NULL_HANDLE, VkPipelineStageFlags2 wait_stage = 0,
                VkSemaphore signal = VK_NULL_HANDLE);
    // Waits for the current slot's submission.
    void wait();
    // Waits for every slot: nothing the ring submitted is still running afterwards.
    void wait_all();
    // Without waiting: true when nothing the ring submitted is still running (wait_all() would return
    // at once).
    bool idle() const;

    FrameSlot& current() { return slots_[current_]; }
    std::uint32_t slot_count() const { return std::uint32_t(slots_.size()); }

private:
    void begin(FrameSlot& slot);
    void wait(FrameSlot& slot);

    const Device& device_;
    std::vector<FrameSlot> slots_;
    std::uint32_t current_ = 0;
};

}  // namespace brume::vk
