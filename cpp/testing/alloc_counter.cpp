#include "alloc_counter.hpp"

#include <atomic>
#include <cstdlib>
#include <new>

// Under AddressSanitizer the allocator belongs to ASan: interposing malloc (forwarding to glibc's
// __libc_malloc) hands ASan memory it never allocated and the process crashes before main. There
// the count comes from ASan's own allocation hook instead, which sees malloc, calloc, realloc,
// the aligned variants and operator new alike; nothing is interposed.
#if defined(__SANITIZE_ADDRESS__)
#define KILOLOOP_ALLOC_COUNTER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define KILOLOOP_ALLOC_COUNTER_ASAN 1
#endif
#endif

namespace {
std::atomic<std::size_t> g_allocations{0};
inline void count() noexcept { g_allocations.fetch_add(1, std::memory_order_relaxed); }
}  // namespace

namespace kiloloop::testing {
std::size_t allocation_count() noexcept { return g_allocations.load(std::memory_order_relaxed); }
bool allocation_counter_uses_sanitizer_hook() noexcept {
#ifdef KILOLOOP_ALLOC_COUNTER_ASAN
  return true;
#else
  return false;
#endif
}
}  // namespace kiloloop::testing

#ifdef KILOLOOP_ALLOC_COUNTER_ASAN

// sanitizer/allocator_interface.h (not shipped with every compiler's headers).
extern "C" int __sanitizer_install_malloc_and_free_hooks(
    void (*malloc_hook)(const volatile void*, std::size_t), void (*free_hook)(const volatile void*));

namespace {
void on_malloc(const volatile void*, std::size_t) { count(); }
void on_free(const volatile void*) {}
// Installed before main (static initialization of this translation unit).
const int g_hooks_installed = __sanitizer_install_malloc_and_free_hooks(on_malloc, on_free);
}  // namespace

#else  // the malloc-level interposer

// glibc's real allocator entry points, so our interposers can forward without recursion.
extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void* __libc_memalign(std::size_t, std::size_t);
void __libc_free(void*);
}

extern "C" {
void* malloc(std::size_t n) {
  count();
  return __libc_malloc(n);
}
void* calloc(std::size_t n, std::size_t size) {
  count();
  return __libc_calloc(n, size);
}
void* realloc(void* p, std::size_t n) {
  count();
  return __libc_realloc(p, n);
}
void* memalign(std::size_t align, std::size_t n) {
  count();
  return __libc_memalign(align, n);
}
void* aligned_alloc(std::size_t align, std::size_t n) {
  count();
  return __libc_memalign(align, n);
}
int posix_memalign(void** out, std::size_t align, std::size_t n) {
  count();
  void* p = __libc_memalign(align, n);
  if (p == nullptr) return 12;  // ENOMEM
  *out = p;
  return 0;
}
void free(void* p) { __libc_free(p); }
}

// operator new is counted here as well as in malloc (libstdc++'s new calls malloc): a new that
// bypassed malloc would still be seen. Each new therefore counts twice; tests compare with zero.
void* operator new(std::size_t n) {
  count();
  void* p = std::malloc(n ? n : 1);
  if (p == nullptr) throw std::bad_alloc();
  return p;
}
void* operator new[](std::size_t n) { return operator new(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  count();
  return std::malloc(n ? n : 1);
}
void* operator new[](std::size_t n, const std::nothrow_t& t) noexcept { return operator new(n, t); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

#endif  // KILOLOOP_ALLOC_COUNTER_ASAN
