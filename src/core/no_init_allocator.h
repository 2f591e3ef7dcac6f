// An allocator whose value-less construction does nothing, for std::vectors of hundreds of
// megabytes (an environment map's texels and sampling tables) whose every element is written
// before it is read: resize() then only reserves the memory, and the pages are first touched
// (and cleared by the kernel) by the threads that fill them, not zero-filled once more by one
// thread beforehand. Only for implicit-lifetime element types (trivially copyable and
// destructible), where leaving the bytes as they are creates the objects.
#pragma once
#include <memory>
#include <type_traits>
#include <utility>

namespace spt {

template <class T>
struct NoInitAllocator : std::allocator<T> {
    static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>);
    using value_type = T;
    template <class U>
    struct rebind {
        using other = NoInitAllocator<U>;
    };
    NoInitAllocator() = default;
    template <class U>
    NoInitAllocator(const NoInitAllocator<U>&) noexcept {}

    /// resize(n) and vector(n): no write.
    template <class U>
    void construct(U*) noexcept {}
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};

template <class T, class U>
bool operator==(const NoInitAllocator<T>&, const NoInitAllocator<U>&) noexcept {
    return true;
}

}  // namespace spt
