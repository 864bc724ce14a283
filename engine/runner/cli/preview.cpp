#include "cli/preview.hpp"

#include <iostream>

namespace loom::runner {

namespace {

// What SaveImage's body reads: the partial image, the preview's path, and
// every other input at its default.
class PreviewHost final : public NodeHost {
 public:
  PreviewHost(const NodeSpec& spec, Value image, const std::filesystem::path& file)
      : spec_(spec), image_(std::move(image)), path_(Value::make<std::string>(file.string())) {}
  Value fetch_input(int index) override {
    const InputSpec& in = spec_.inputs[static_cast<std::size_t>(index)];
    if (in.name == "image") return image_;
    if (in.name == "path") return path_;
    return Value(in.type, in.type->from_json(in.default_value));
  }
  bool input_set(int) const override { return true; }
  void report_progress(double, std::string_view) override {}
  void report(bool warning, std::string text) override {
    if (warning) std::cerr << "warning: preview: " << text << "\n";
  }
  bool cancelled() const override { return false; }
  std::shared_ptr<void> scratch(std::uint64_t, const std::function<std::shared_ptr<void>()>& make) override {
    return make();
  }
  std::shared_ptr<void> sequence_state(const std::function<std::shared_ptr<void>()>& make) override {
    return make();
  }

 private:
  const NodeSpec& spec_;
  Value image_, path_;
};

}  // namespace

const NodeType* save_image_type(LoadedGraph& loaded) {
  try {
    loaded.loader->load_for({"SaveImage"});
  } catch (const std::exception& e) {
    std::cerr << "error: --preview: " << e.what() << "\n";
    return nullptr;
  }
  const NodeType* save = loaded.registry->find("SaveImage");
  if (!save) std::cerr << "error: --preview writes with SaveImage (the io plugin), which was not found\n";
  return save;
}

PreviewWriter::PreviewWriter(Observer& next, const NodeType& save, std::filesystem::path file, double every_seconds)
    : next_(next),
      save_(save),
      file_(std::filesystem::absolute(file)),
      every_(std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(every_seconds))) {}

bool PreviewWriter::wants_partial(const std::string&) const {
  std::lock_guard lock(mutex_);
  return !failed_ && (written_ == 0 || Clock::now() - last_ >= every_);
}

void PreviewWriter::node_partial(const std::string& id, const std::string&, const Value& value,
                                 const PartialInfo&) {
  if (value.type()->name != "Image") return;
  std::lock_guard lock(mutex_);  // one write at a time, also from nodes running side by side
  if (failed_ || (written_ > 0 && Clock::now() - last_ < every_)) return;
  PreviewHost host(save_.spec, value, file_);
  Inputs in(save_.spec, host);
  Outputs out(save_.spec);
  const std::string node = "preview of " + id;
  const std::filesystem::path here = file_.parent_path();
  Context ctx(host, node, 0, here, here);
  try {
    save_.run(in, out, ctx);
  } catch (const std::exception& e) {  // the render goes on: only its preview stops
    failed_ = true;
    next_.node_message(id, true, std::string("--preview stopped: ") + e.what());
    return;
  }
  last_ = Clock::now();
  ++written_;
}

}  // namespace loom::runner
