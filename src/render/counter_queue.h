// The simplest queue: a batch of items in an array and one atomic counter that hands out
// the next index (one fetch_add per item, no lock, no per-cell state).
#pragma once
#include <atomic>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace spt {

/// Same contract as MutexQueue, plus the one that makes a single counter enough: push() only
/// once every item of the previous batch has been popped and those pop() calls have returned
/// (the renderer pushes a pass, or a wavefront stage, after every task of the one before
/// has finished). A batch holds fewer than 2^32 items.
///
/// Why it is correct under the C++ memory model: m_state packs the batch size (high 32 bits)
/// and the next index (low 32 bits) in one word, so a claim, fetch_add(1), reads both from
/// the same batch atomically. push() writes the items, then stores (size, 0) with release;
/// a claim that reads that word (acquire; later claims read it through the release sequence
/// of the RMWs) sees the items. A claim past the size takes nothing and leaves the items
/// alone, so the producer may overwrite them (contract above). Each worker makes at most
/// one failed claim per m_epoch value, so the index exceeds the size by at most the worker
/// count. Sleeping works as in RingQueue: wait on m_epoch, which push and close increment.
template <typename T>
class CounterQueue {
public:
    void push(std::span<const T> items) {
        m_items.assign(items.begin(), items.end());
        m_state.store(std::uint64_t(m_items.size()) << 32, std::memory_order_release);
        m_epoch.fetch_add(1, std::memory_order_release);
        m_epoch.notify_all();
    }

    /// Blocks until an item is available; nullopt once the queue is closed and empty.
    std::optional<T> pop() {
        for (;;) {
            const std::uint32_t epoch = m_epoch.load(std::memory_order_acquire);
            const std::uint64_t state = m_state.fetch_add(1, std::memory_order_acq_rel);
            const auto size = static_cast<std::uint32_t>(state >> 32);
            const auto index = static_cast<std::uint32_t>(state);
            if (index < size) return m_items[index];
            if (m_closed.load(std::memory_order_acquire)) return std::nullopt;
            m_epoch.wait(epoch, std::memory_order_acquire);
        }
    }

    void close() {
        m_closed.store(true, std::memory_order_release);
        m_epoch.fetch_add(1, std::memory_order_release);
        m_epoch.notify_all();
    }

private:
    static constexpr std::size_t kLine = 64;
    std::vector<T> m_items;
    alignas(kLine) std::atomic<std::uint64_t> m_state{0};
    alignas(kLine) std::atomic<std::uint32_t> m_epoch{0};
    std::atomic<bool> m_closed{false};
};

}  // namespace spt
