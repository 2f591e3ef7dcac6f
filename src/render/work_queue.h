// A thread-safe FIFO queue: one producer pushes work items, many workers pop them until the
// queue is closed and drained.
#pragma once
#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>

namespace spt {

template <typename T>
class WorkQueue {
public:
    void push(T item) {
        {
            const std::lock_guard lock(m_mutex);
            m_items.push_back(std::move(item));
        }
        m_ready.notify_one();
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
