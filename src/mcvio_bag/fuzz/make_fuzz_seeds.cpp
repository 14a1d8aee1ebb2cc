// Writes small valid bags as seed corpora for the fuzz targets:
//   make_fuzz_seeds MCAP_CORPUS_DIR SQLITE_CORPUS_DIR [METADATA_CORPUS_DIR]
#include <filesystem>
#include <iostream>
#include <string>

#include "mcvio/bag/bag_writer.hpp"

int main(int argc, char** argv) {
  if (argc != 3 && argc != 4) {
    std::cerr << "usage: make_fuzz_seeds MCAP_DIR SQLITE_DIR [METADATA_DIR]\n";
    return 2;
  }
  namespace fs = std::filesystem;
  const fs::path work = fs::temp_directory_path() / "mcvio_fuzz_seeds";
  fs::remove_all(work);
  int n = 0;
  for (const std::string storage : {"mcap", "sqlite3"}) {
    for (auto c : {mcvio::bag::Compression::None, mcvio::bag::Compression::Zstd,
                   mcvio::bag::Compression::Lz4}) {
      const fs::path bag = work / ("seed" + std::to_string(n++));
      mcvio::bag::BagWriterOptions o;
      o.storage = storage;
      o.compression = c;
      o.chunk_size = 200;
      {
        mcvio::bag::BagWriter w(bag, o);
        mcvio::bag::TopicInfo t{
            "/a", "std_msgs/msg/String", "cdr", "- history: 1\n", "string data\n", ""};
        w.addTopic(t);
        for (int i = 0; i < 6; ++i) {
          const std::string s(static_cast<std::size_t>(20 + i * 7), static_cast<char>('a' + i));
          w.write("/a", 100 + i, 90 + i, reinterpret_cast<const std::uint8_t*>(s.data()), s.size());
        }
      }
      for (const auto& e : fs::directory_iterator(bag)) {
        const auto ext = e.path().extension();
        if (ext == ".mcap")
          fs::copy_file(e.path(), fs::path(argv[1]) / (bag.filename().string() + ".mcap"),
                        fs::copy_options::overwrite_existing);
        if (argc == 4 && e.path().filename() == "metadata.yaml") {
          fs::copy_file(e.path(), fs::path(argv[3]) / (bag.filename().string() + ".yaml"),
                        fs::copy_options::overwrite_existing);
        }
        if (ext == ".db3")
          fs::copy_file(e.path(), fs::path(argv[2]) / (bag.filename().string() + ".db3"),
                        fs::copy_options::overwrite_existing);
      }
    }
  }
  fs::remove_all(work);
  return 0;
}
