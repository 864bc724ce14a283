#include "cli/preview.hpp"

#include <iostream>

#include "loom/call_node.hpp"

namespace loom::runner {

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
  NodeCall call;  // SaveImage of the partial image to the preview's path, every other input at its default
  call.values.emplace("image", value);
  call.literals["path"] = file_.string();
  call.id = "preview of " + id;
  call.dir = file_.parent_path();
  call.report = [](bool warning, const std::string& text) {
    if (warning) std::cerr << "warning: preview: " << text << "\n";
  };
  try {
    call_node(save_, call);
  } catch (const std::exception& e) {  // the render goes on: only its preview stops
    failed_ = true;
    next_.node_message(id, true, std::string("--preview stopped: ") + e.what());
    return;
  }
  last_ = Clock::now();
  ++written_;
}

}  // namespace loom::runner
