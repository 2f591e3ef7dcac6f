// The reference work queue: a deque behind a mutex, workers sleeping on a condition variable.
#pragma once
#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>
#include <span>

namespace spt {

/// FIFO for one producer and many consumers. Contract (shared by the three queue kinds, see
/// work_queue.h): push batches, pop until close() and empty.
template <typename T>
class MutexQueue {
public:
    void push(std::span<const T> items) {
        {
            const std::lock_guard lock(m_mutex);
            m_items.insert(m_items.end(), items.begin(), items.end());
        }
        m_ready.notify_all();
    }

    /// Blocks until an item is available; nullopt once the queue is closed and empty.
    std::optional<T> pop() {
        std::unique_lock lock(m_mutex);
        m_ready.wait(lock, [&] { return !m_items.empty() || m_closed; });
        if (m_items.empty()) return std::nullopt;
        T item = std::move(m_items.front());
        m_items.pop_front();
        return item;
    }

    /// No more items will come: wakes every waiting worker.
    void close() {
        {
            const std::lock_guard lock(m_mutex);
            m_closed = true;
        }
        m_ready.notify_all();
    }

private:
    std::mutex m_mutex;
    std::condition_variable m_ready;
    std::deque<T> m_items;
    bool m_closed = false;
};

}  // namespace spt
