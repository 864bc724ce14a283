// Large OpenCV buffers on transparent huge pages. A fresh buffer costs a page
// fault at each first touch of a 4-kB page: on the virtual machines Loom runs
// on, 10-40 us each, so filling a new 100-MB image (a 3840x2160 RGB float)
// took 470 ms where copying into a touched one takes 9 ms. With 2-MB pages
// (madvise(MADV_HUGEPAGE), honoured when the kernel's THP setting is
// "madvise" or "always") the same first fill takes 32-60 ms
// (docs/architecture.md, decision 27). Small buffers keep OpenCV's allocator.
//
// Installed as OpenCV's default Mat allocator when libloom_types is loaded:
// every plugin that makes images shares it.
#include <dlfcn.h>
#include <sys/mman.h>

#include <cstdlib>
#include <new>

#include <opencv2/core.hpp>

namespace loom {
namespace {

constexpr std::size_t kHugePage = std::size_t(1) << 21;
constexpr std::size_t kHugeFrom = std::size_t(8) << 20;  // below: OpenCV's own (at most 25% rounding lost)

class HugePageAllocator final : public cv::MatAllocator {
 public:
  cv::UMatData* allocate(int dims, const int* sizes, int type, void* data0, std::size_t* step,
                         cv::AccessFlag flags, cv::UMatUsageFlags usage) const override {
    std::size_t total = CV_ELEM_SIZE(type);
    for (int i = dims - 1; i >= 0; --i) {
      if (step) {
        if (data0 && step[i] != cv::Mat::AUTO_STEP) total = step[i];
        else step[i] = total;
      }
      total *= std::size_t(sizes[i]);
    }
    if (data0 || total < kHugeFrom) return standard()->allocate(dims, sizes, type, data0, step, flags, usage);
    const std::size_t rounded = (total + kHugePage - 1) / kHugePage * kHugePage;
    void* data = std::aligned_alloc(kHugePage, rounded);
    if (!data) throw std::bad_alloc();
    madvise(data, rounded, MADV_HUGEPAGE);  // a hint: refused or ignored, the pages are small ones
    auto* u = new cv::UMatData(this);
    u->data = u->origdata = static_cast<uchar*>(data);
    u->size = total;
    return u;
  }
  bool allocate(cv::UMatData* u, cv::AccessFlag, cv::UMatUsageFlags) const override { return u != nullptr; }
  void deallocate(cv::UMatData* u) const override {
    if (!u) return;
    CV_Assert(u->urefcount == 0 && u->refcount == 0);
    std::free(u->origdata);
    delete u;
  }

  static void pin() {}  // an address inside this library, for dladdr

 private:
  static cv::MatAllocator* standard() { return cv::Mat::getStdAllocator(); }
};

// Never destroyed, and this library never unloaded (a plugin's hot reload
// could otherwise unload it): images made through it may outlive both.
const bool installed = [] {
  Dl_info self;
  if (dladdr(reinterpret_cast<void*>(&HugePageAllocator::pin), &self) && self.dli_fname)
    dlopen(self.dli_fname, RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);
  cv::Mat::setDefaultAllocator(new HugePageAllocator);
  return true;
}();

}  // namespace
}  // namespace loom
