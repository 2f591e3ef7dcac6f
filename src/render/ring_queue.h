// A bounded lock-free ring (Vyukov's MPMC queue): one sequence number per cell says whose turn
// it is, so producers and consumers claim cells with one compare-and-swap and never lock.
#pragma once
#include <algorithm>
#include <atomic>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <optional>
#include <span>
#include <thread>

namespace spt {

/// Same contract as MutexQueue. `capacity` is rounded up to a power of two; a push that finds
/// the ring full wakes the consumers and yields until one frees a cell (the renderer sizes
/// the ring to hold a pass of up to 65536 tasks, so it waits only past that).
///
/// Why it is correct under the C++ memory model: cell i of lap k has sequence k·N + i when
/// free for the producer and k·N + i + 1 when it holds an item. Positions are claimed by CAS
/// on enqueue/dequeue counters (relaxed: they only hand out cells, they publish no data).
/// The producer writes the item, then stores seq = pos + 1 with release; a consumer loads
/// seq with acquire, so seeing pos + 1 makes the item's bytes visible. The consumer moves the
/// item out, then stores seq = pos + N with release; the producer's acquire load of that
/// value orders its next write of the cell after the read. A stale counter only makes the
/// sequence test fail and the thread re-read the counter (it never takes a wrong cell).
/// Sleeping: consumers that find the ring empty wait on m_epoch (C++20 atomic wait, a futex
/// on Linux), which push and close() increment with release after publishing, so a pop that
/// read the epoch before a push either sees the item or sees the epoch change: no lost wake-up.
template <typename T>
class RingQueue {
public:
    explicit RingQueue(std::size_t capacity)
        : m_mask(std::bit_ceil(std::max<std::size_t>(capacity, 2)) - 1),
          m_cells(std::make_unique<Cell[]>(m_mask + 1)) {
        for (std::size_t i = 0; i <= m_mask; ++i) m_cells[i].seq.store(i, std::memory_order_relaxed);
    }

    void push(std::span<const T> items) {
        for (const T& item : items)
            while (!try_push(item)) {
                // Full: wake the consumers for what is in (they may have gone to sleep on an
                // empty ring before this batch), then give them the core.
                publish();
                std::this_thread::yield();
            }
        publish();
    }

    /// Blocks until an item is available; nullopt once the queue is closed and empty.
    std::optional<T> pop() {
        for (;;) {
            const std::uint32_t epoch = m_epoch.load(std::memory_order_acquire);
            if (std::optional<T> item = try_pop()) return item;
            // close() publishes after every push: seeing it, one more try drains the ring.
            if (m_closed.load(std::memory_order_acquire)) return try_pop();
            m_epoch.wait(epoch, std::memory_order_acquire);
        }
    }

    void close() {
        m_closed.store(true, std::memory_order_release);
        publish();
    }

    /// One attempt: false when the ring is full.
    bool try_push(const T& item) {
        std::size_t pos = m_enqueue.load(std::memory_order_relaxed);
        for (;;) {
            Cell& cell = m_cells[pos & m_mask];
            const std::size_t seq = cell.seq.load(std::memory_order_acquire);
            const auto diff = static_cast<std::ptrdiff_t>(seq - pos);
            if (diff == 0) {
                if (m_enqueue.compare_exchange_weak(pos, pos + 1, std::memory_order_relaxed)) {
                    cell.item = item;
                    cell.seq.store(pos + 1, std::memory_order_release);
                    return true;
                }
            } else if (diff < 0) {
                return false;  // the cell still holds the item of the previous lap: full
            } else {
                pos = m_enqueue.load(std::memory_order_relaxed);
            }
        }
    }

    /// One attempt: nullopt when the ring is empty.
    std::optional<T> try_pop() {
        std::size_t pos = m_dequeue.load(std::memory_order_relaxed);
        for (;;) {
            Cell& cell = m_cells[pos & m_mask];
            const std::size_t seq = cell.seq.load(std::memory_order_acquire);
            const auto diff = static_cast<std::ptrdiff_t>(seq - (pos + 1));
            if (diff == 0) {
                if (m_dequeue.compare_exchange_weak(pos, pos + 1, std::memory_order_relaxed)) {
                    T item = std::move(cell.item);
                    cell.seq.store(pos + m_mask + 1, std::memory_order_release);
                    return item;
                }
            } else if (diff < 0) {
                return std::nullopt;  // not yet written in this lap: empty
            } else {
                pos = m_dequeue.load(std::memory_order_relaxed);
            }
        }
    }

private:
    /// Makes the items pushed so far visible to sleeping consumers.
    void publish() {
        m_epoch.fetch_add(1, std::memory_order_release);
        m_epoch.notify_all();
    }
    struct Cell {
        std::atomic<std::size_t> seq;
        T item{};
    };
    // The two counters on their own cache lines: producers and consumers do not share them.
    static constexpr std::size_t kLine = 64;
    const std::size_t m_mask;
    std::unique_ptr<Cell[]> m_cells;
    alignas(kLine) std::atomic<std::size_t> m_enqueue{0};
    alignas(kLine) std::atomic<std::size_t> m_dequeue{0};
    alignas(kLine) std::atomic<std::uint32_t> m_epoch{0};
    std::atomic<bool> m_closed{false};
};

}  // namespace spt
