#include "mcvio/conflict/landmark_motion_classifier.hpp"

namespace mcvio::conflict {

bool LandmarkMotionClassifier::addVerdict(std::uint64_t track_id, bool inconsistent) {
  if (moving_.count(track_id) != 0) return false;
  int& c = count_[track_id];
  c = inconsistent ? c + 1 : (c > 0 ? c - 1 : 0);
  int& agreeing = agreeing_[track_id];
  agreeing = inconsistent ? 0 : agreeing + 1;
  if (c == 0 && agreeing >= confirmations_)
    confirmed_.insert(track_id);
  else
    confirmed_.erase(track_id);
  if (c < strikes_) return false;
  moving_.insert(track_id);
  count_.erase(track_id);
  agreeing_.erase(track_id);
  return true;
}

void LandmarkMotionClassifier::forget(std::uint64_t track_id) {
  count_.erase(track_id);
  moving_.erase(track_id);
  confirmed_.erase(track_id);
  agreeing_.erase(track_id);
}

void LandmarkMotionClassifier::clear() {
  count_.clear();
  moving_.clear();
  confirmed_.clear();
  agreeing_.clear();
}

}  // namespace mcvio::conflict
