#include "render/vk/frame_ring.h"

#include "render/vk/vk_check.h"

#include <string>

namespace brume::vk {

FrameRing::FrameRing(const Device& device, std::uint32_t slots) : device_(device) {
    if (slots == 0) slots = 1;
    slots_.resize(slots);
    for (std::uint32_t i = 0; i < slots; ++i) {
        FrameSlot& s = slots_[i];
        const std::string name = "frame_slot[" + std::to_string(i) + "]";
        VkCommandPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        pool_info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
        pool_info.queueFamilyIndex = device.queue_family();
        VkCommandPool pool;
        VK_CHECK(vkCreateCommandPool(device.get(), &pool_info, nullptr, &pool));
        s.pool = UniqueCommandPool(device.get(), pool);
        device.set_name(VK_OBJECT_TYPE_COMMAND_POOL, pool, (name + ".commands").c_str());
        VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
        alloc.commandPool = pool;
        alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        alloc.commandBufferCount = 1;
        VK_CHECK(vkAllocateCommandBuffers(device.get(), &alloc, &s.cmd));
        VkFenceCreateInfo fence_info{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        VkFence fence;
        VK_CHECK(vkCreateFence(device.get(), &fence_info, nullptr, &fence));
        s.done = UniqueFence(device.get(), fence);
        device.set_name(VK_OBJECT_TYPE_FENCE, fence, (name + ".done").c_str());
        VkSemaphoreCreateInfo sem_info{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        VkSemaphore acquired, ready;
        VK_CHECK(vkCreateSemaphore(device.get(), &sem_info, nullptr, &acquired));
        s.image_acquired = UniqueSemaphore(device.get(), acquired);
        VK_CHECK(vkCreateSemaphore(device.get(), &sem_info, nullptr, &ready));
        s.ready_to_present = UniqueSemaphore(device.get(), ready);
        device.set_name(VK_OBJECT_TYPE_SEMAPHORE, acquired, (name + ".image_acquired").c_str());
        device.set_name(VK_OBJECT_TYPE_SEMAPHORE, ready, (name + ".ready_to_present").c_str());
    }
    current_ = slots - 1;  // the first begin_next() takes slot 0
}

FrameRing::~FrameRing() {
    // Destroying a pool or fence that the GPU still uses is an error: wait first, never throw here.
    for (FrameSlot& s : slots_) {
        if (!s.pending) continue;
        VkFence fence = s.done;
        vkWaitForFences(device_.get(), 1, &fence, VK_TRUE, UINT64_MAX);
    }
}

void FrameRing::begin(FrameSlot& slot) {
    VK_CHECK(vkResetCommandBuffer(slot.cmd, 0));
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VK_CHECK(vkBeginCommandBuffer(slot.cmd, &begin));
}

FrameSlot& FrameRing::begin_next() {
    current_ = (current_ + 1) % slot_count();
    FrameSlot& slot = slots_[current_];
    wait(slot);
    begin(slot);
    return slot;
}

FrameSlot& FrameRing::begin_again() {
    FrameSlot& slot = slots_[current_];
    wait(slot);
    begin(slot);
    return slot;
}

void FrameRing::submit(VkSemaphore wait_semaphore, VkPipelineStageFlags2 wait_stage, VkSemaphore signal) {
    FrameSlot& slot = slots_[current_];
    VK_CHECK(vkEndCommandBuffer(slot.cmd));
    VkCommandBufferSubmitInfo cmd{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
    cmd.commandBuffer = slot.cmd;
    VkSemaphoreSubmitInfo wait_info{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
    wait_info.semaphore = wait_semaphore;
    wait_info.stageMask = wait_stage;
    VkSemaphoreSubmitInfo signal_info{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
    signal_info.semaphore = signal;
    signal_info.stageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    VkSubmitInfo2 submit{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
    submit.commandBufferInfoCount = 1;
    submit.pCommandBufferInfos = &cmd;
    submit.waitSemaphoreInfoCount = wait_semaphore ? 1 : 0;
    submit.pWaitSemaphoreInfos = &wait_info;
    submit.signalSemaphoreInfoCount = signal ? 1 : 0;
    submit.pSignalSemaphoreInfos = &signal_info;
    {
        const auto queue_lock = device_.lock_queue();  // the queue is shared with other threads' rings
        VK_CHECK(vkQueueSubmit2(device_.queue(), 1, &submit, slot.done));
    }
    slot.pending = true;
}

void FrameRing::wait(FrameSlot& slot) {
    if (!slot.pending) return;
    VkFence fence = slot.done;
    VK_CHECK(vkWaitForFences(device_.get(), 1, &fence, VK_TRUE, UINT64_MAX));
    VK_CHECK(vkResetFences(device_.get(), 1, &fence));
    slot.pending = false;
}

void FrameRing::wait() { wait(slots_[current_]); }

bool FrameRing::idle() const {
    for (const FrameSlot& s : slots_) {
        if (!s.pending) continue;
        const VkResult r = vkGetFenceStatus(device_.get(), s.done);
        if (r == VK_NOT_READY) return false;
        VK_CHECK(r);
    }
    return true;
}

void FrameRing::wait_all() {
    for (FrameSlot& s : slots_) wait(s);
}

}  // namespace brume::vk
