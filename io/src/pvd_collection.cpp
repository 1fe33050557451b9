#include "pvd_collection.h"

#include "io/atomic_file.h"
#include "number_format.h"

namespace fq::detail {

namespace {

std::string xml_attribute_escape(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (const char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out.push_back(c);
    }
  }
  return out;
}

}  // namespace

PvdCollection::PvdCollection(std::filesystem::path pvd_file) : file_(std::move(pvd_file)) {}

void PvdCollection::add(double time_s, const std::string& relative_file) {
  // Shortest round-trip form: the time a reader parses is bitwise the time
  // stored in the frame's TimeValue field.
  entries_ += "    <DataSet timestep=\"";
  append_number(entries_, time_s);
  entries_ += "\" group=\"\" part=\"0\" file=\"";
  entries_ += xml_attribute_escape(relative_file);
  entries_ += "\"/>\n";
  ++count_;
  write();
}

void PvdCollection::write() const {
  std::string doc;
  doc.reserve(entries_.size() + 200);
  doc += "<?xml version=\"1.0\"?>\n";
  doc += "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n";
  doc += "  <Collection>\n";
  doc += entries_;
  doc += "  </Collection>\n";
  doc += "</VTKFile>\n";
  write_file_atomically(file_, doc);
}

}  // namespace fq::detail
