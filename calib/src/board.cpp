#include "holo/calib/board.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <opencv2/aruco.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "holo/core/error.hpp"

namespace holo::calib {

namespace {

const std::map<std::string, int>& dictionaries() {
  static const std::map<std::string, int> names = {{"DICT_4X4_50", cv::aruco::DICT_4X4_50},
                                                   {"DICT_4X4_100", cv::aruco::DICT_4X4_100},
                                                   {"DICT_4X4_250", cv::aruco::DICT_4X4_250},
                                                   {"DICT_4X4_1000", cv::aruco::DICT_4X4_1000},
                                                   {"DICT_5X5_50", cv::aruco::DICT_5X5_50},
                                                   {"DICT_5X5_100", cv::aruco::DICT_5X5_100},
                                                   {"DICT_5X5_250", cv::aruco::DICT_5X5_250},
                                                   {"DICT_5X5_1000", cv::aruco::DICT_5X5_1000},
                                                   {"DICT_6X6_50", cv::aruco::DICT_6X6_50},
                                                   {"DICT_6X6_100", cv::aruco::DICT_6X6_100},
                                                   {"DICT_6X6_250", cv::aruco::DICT_6X6_250},
                                                   {"DICT_6X6_1000", cv::aruco::DICT_6X6_1000},
                                                   {"DICT_7X7_50", cv::aruco::DICT_7X7_50},
                                                   {"DICT_7X7_100", cv::aruco::DICT_7X7_100},
                                                   {"DICT_7X7_250", cv::aruco::DICT_7X7_250},
                                                   {"DICT_7X7_1000", cv::aruco::DICT_7X7_1000},
                                                   {"DICT_ARUCO_ORIGINAL", cv::aruco::DICT_ARUCO_ORIGINAL}};
  return names;
}

std::vector<std::string> split(const std::string& text, char sep) {
  std::vector<std::string> parts;
  std::stringstream in(text);
  std::string part;
  while (std::getline(in, part, sep)) parts.push_back(part);
  if (!text.empty() && text.back() == sep) parts.emplace_back();
  return parts;
}

double parsePositive(const std::string& text, const std::string& source, const std::string& field) {
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || !std::isfinite(v) || !(v > 0))
    throw InputError(source, field, "a length in metres > 0", "\"" + text + "\"");
  return v;
}

cv::Mat toGrey(const cv::Mat& image) {
  if (image.empty()) return image;
  cv::Mat grey;
  if (image.channels() == 3)
    cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  else if (image.channels() == 4)
    cv::cvtColor(image, grey, cv::COLOR_BGRA2GRAY);
  else
    grey = image;
  if (grey.depth() != CV_8U) grey.convertTo(grey, CV_8U);
  return grey;
}

}  // namespace

BoardSpec BoardSpec::parse(const std::string& text, const std::string& source) {
  const auto parts = split(text, ':');
  const std::string forms = "chessboard:COLSxROWS:SQUARE_M or charuco:COLSxROWS:SQUARE_M:MARKER_M:DICT";
  if (parts.empty()) throw InputError(source, "board", forms, "\"" + text + "\"");
  BoardSpec spec;
  if (parts[0] == "chessboard" && parts.size() == 3)
    spec.kind = Kind::Chessboard;
  else if (parts[0] == "charuco" && parts.size() == 5)
    spec.kind = Kind::Charuco;
  else
    throw InputError(source, "board", forms, "\"" + text + "\"");

  const std::string& size = parts[1];
  const auto x = size.find_first_of("xX");
  int cols = 0, rows = 0;
  try {
    std::size_t used_c = 0, used_r = 0;
    if (x != std::string::npos) {
      cols = std::stoi(size.substr(0, x), &used_c);
      rows = std::stoi(size.substr(x + 1), &used_r);
    }
    if (x == std::string::npos || used_c != x || used_r != size.size() - x - 1) cols = rows = 0;
  } catch (const std::exception&) {
    cols = rows = 0;
  }
  const int min_size = spec.kind == Kind::Chessboard ? 2 : 3;
  if (cols < min_size || rows < min_size || cols > 100 || rows > 100)
    throw InputError(source, "board size",
                     "COLSxROWS with " + std::to_string(min_size) + " to 100 " +
                         (spec.kind == Kind::Chessboard ? "inner corners" : "squares") + " each",
                     "\"" + size + "\"");
  spec.cols = cols;
  spec.rows = rows;
  spec.square_m = parsePositive(parts[2], source, "square size");
  if (spec.kind == Kind::Charuco) {
    spec.marker_m = parsePositive(parts[3], source, "marker size");
    if (spec.marker_m >= spec.square_m)
      throw InputError(source, "marker size", "a marker smaller than the square (" + parts[2] + " m)",
                       parts[3]);
    std::string dict = parts[4];
    for (auto& ch : dict) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
    if (dict.rfind("DICT_", 0) != 0) dict = "DICT_" + dict;
    if (!dictionaries().count(dict)) {
      std::string known;
      for (const auto& [name, id] : dictionaries()) known += (known.empty() ? "" : ", ") + name;
      throw InputError(source, "dictionary", "one of " + known, "\"" + parts[4] + "\"");
    }
    spec.dictionary = dict;
    const int needed = (cols * rows) / 2;  // markers sit on every other square
    const int available = cv::aruco::getPredefinedDictionary(dictionaries().at(dict))->bytesList.rows;
    if (needed > available)
      throw InputError(source, "dictionary",
                       "a dictionary with at least " + std::to_string(needed) + " markers",
                       dict + " (" + std::to_string(available) + ")");
  }
  return spec;
}

std::string BoardSpec::describe() const {
  std::ostringstream out;
  if (kind == Kind::Chessboard)
    out << "chessboard " << cols << "x" << rows << " inner corners, " << square_m * 1000 << " mm squares";
  else
    out << "ChArUco " << cols << "x" << rows << " squares, " << square_m * 1000 << " mm squares, "
        << marker_m * 1000 << " mm markers, " << dictionary;
  return out.str();
}

cv::Ptr<cv::aruco::CharucoBoard> BoardSpec::charucoBoard() const {
  HOLO_ASSERT(kind == Kind::Charuco);
  return cv::aruco::CharucoBoard::create(cols, rows, static_cast<float>(square_m),
                                         static_cast<float>(marker_m),
                                         cv::aruco::getPredefinedDictionary(dictionaries().at(dictionary)));
}

std::vector<cv::Point3f> BoardSpec::allCorners() const {
  if (kind == Kind::Charuco) return charucoBoard()->chessboardCorners;
  std::vector<cv::Point3f> corners;
  corners.reserve(static_cast<std::size_t>(cols * rows));
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      corners.emplace_back(static_cast<float>(c * square_m), static_cast<float>(r * square_m), 0.0f);
  return corners;
}

cv::Rect2d BoardSpec::extent() const {
  if (kind == Kind::Charuco) return {0.0, 0.0, cols * square_m, rows * square_m};
  return {-square_m, -square_m, (cols + 1) * square_m, (rows + 1) * square_m};
}

double BoardDetection::widthFraction(int image_width) const {
  if (image_points.empty() || image_width <= 0) return 0.0;
  const cv::Rect2f box = cv::boundingRect(image_points);
  return static_cast<double>(box.width) / image_width;
}

BoardDetection detectBoard(const BoardSpec& board, const cv::Mat& image) {
  BoardDetection out;
  const cv::Mat grey = toGrey(image);
  if (grey.empty()) return out;
  const std::vector<cv::Point3f> all = board.allCorners();
  if (board.kind == BoardSpec::Kind::Chessboard) {
    std::vector<cv::Point2f> corners;
    const cv::Size pattern(board.cols, board.rows);
    if (!cv::findChessboardCorners(grey, pattern, corners,
                                   cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE))
      return out;
    // OpenCV's sample uses an 11x11 window; smaller squares need a smaller one, or the window
    // would reach the neighbouring corner.
    float spacing = 1e9f;
    for (int i = 0; i + 1 < static_cast<int>(corners.size()); ++i)
      if ((i + 1) % board.cols != 0)
        spacing = std::min(spacing, static_cast<float>(cv::norm(corners[static_cast<std::size_t>(i)] -
                                                                corners[static_cast<std::size_t>(i + 1)])));
    const int half = std::clamp(static_cast<int>(spacing * 0.4f), 2, 5);
    cv::cornerSubPix(grey, corners, cv::Size(half, half), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 30, 0.001));
    out.image_points = corners;
    out.object_points = all;
    out.ids.resize(all.size());
    for (std::size_t i = 0; i < all.size(); ++i) out.ids[i] = static_cast<int>(i);
    return out;
  }
  const auto charuco = board.charucoBoard();
  std::vector<std::vector<cv::Point2f>> marker_corners, rejected;
  std::vector<int> marker_ids;
  const auto params = cv::aruco::DetectorParameters::create();
  cv::aruco::detectMarkers(grey, charuco->dictionary, marker_corners, marker_ids, params, rejected);
  out.markers = static_cast<int>(marker_ids.size());
  if (marker_ids.empty()) return out;
  cv::aruco::refineDetectedMarkers(grey, charuco, marker_corners, marker_ids, rejected);
  out.markers = static_cast<int>(marker_ids.size());
  std::vector<cv::Point2f> corners;
  std::vector<int> ids;
  cv::aruco::interpolateCornersCharuco(marker_corners, marker_ids, grey, charuco, corners, ids);
  if (!corners.empty()) {
    // OpenCV 4.6's interpolated ChArUco corners sit about half a pixel off (measured on synthetic
    // views: +0.5 px in x and y; plain cornerSubPix on the same image gives < 0.01 px). Refine
    // again with a window that stays inside the white gap between a corner and the nearest
    // marker, (square - marker) / 2 wide.
    double marker_px = 0;
    for (const auto& quad : marker_corners)
      marker_px += cv::norm(quad[0] - quad[1]) + cv::norm(quad[1] - quad[2]);
    marker_px /= 2.0 * static_cast<double>(marker_corners.size());
    const double gap_px = marker_px * (board.square_m - board.marker_m) / (2.0 * board.marker_m);
    const int half = std::clamp(static_cast<int>(gap_px * 0.9), 2, 5);
    cv::cornerSubPix(grey, corners, cv::Size(half, half), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 30, 0.001));
  }
  for (std::size_t i = 0; i < ids.size(); ++i) {
    out.image_points.push_back(corners[i]);
    out.ids.push_back(ids[i]);
    out.object_points.push_back(all[static_cast<std::size_t>(ids[i])]);
  }
  return out;
}

cv::Mat drawDetection(const BoardSpec& board, const cv::Mat& image, const BoardDetection& detection) {
  cv::Mat out;
  if (image.channels() == 1)
    cv::cvtColor(toGrey(image), out, cv::COLOR_GRAY2BGR);
  else
    out = image.clone();
  if (detection.image_points.empty()) {
    cv::putText(out, "no board", {10, 30}, cv::FONT_HERSHEY_SIMPLEX, 0.9, {0, 0, 255}, 2);
    return out;
  }
  if (board.kind == BoardSpec::Kind::Chessboard &&
      detection.image_points.size() == static_cast<std::size_t>(board.cols * board.rows))
    cv::drawChessboardCorners(out, cv::Size(board.cols, board.rows), detection.image_points, true);
  else
    cv::aruco::drawDetectedCornersCharuco(out, detection.image_points, cv::noArray(), {0, 255, 0});
  return out;
}

BoardTexture renderBoardTexture(const BoardSpec& board, int pixels_per_square) {
  const int pps = std::max(pixels_per_square, 8);
  const int margin = pps / 2;
  BoardTexture texture;
  const double scale = pps / board.square_m;
  if (board.kind == BoardSpec::Kind::Charuco) {
    const cv::Size size(board.cols * pps + 2 * margin, board.rows * pps + 2 * margin);
    board.charucoBoard()->draw(size, texture.image, margin, 1);
    // Board X, Y = 0 is the outer edge of the squares, i.e. the pixel edge at `margin`; pixel
    // centres sit at integer coordinates, hence the half-pixel shift.
    texture.board_to_pixel = cv::Matx33d(scale, 0, margin - 0.5, 0, scale, margin - 0.5, 0, 0, 1);
    return texture;
  }
  const int squares_x = board.cols + 1, squares_y = board.rows + 1;
  texture.image =
      cv::Mat(squares_y * pps + 2 * margin, squares_x * pps + 2 * margin, CV_8UC1, cv::Scalar(255));
  for (int r = 0; r < squares_y; ++r)
    for (int c = 0; c < squares_x; ++c)
      if ((r + c) % 2 == 0)
        texture.image(cv::Rect(margin + c * pps, margin + r * pps, pps, pps)).setTo(cv::Scalar(0));
  // The first inner corner (board origin) is one square in from the margin.
  const double origin = margin + pps - 0.5;
  texture.board_to_pixel = cv::Matx33d(scale, 0, origin, 0, scale, origin, 0, 0, 1);
  return texture;
}

cv::Mat detectionContactSheet(const std::vector<cv::Mat>& drawn, int columns, int thumb_width) {
  if (drawn.empty()) return {};
  columns = std::max(1, std::min(columns, static_cast<int>(drawn.size())));
  int thumb_height = 0;
  std::vector<cv::Mat> thumbs;
  for (const cv::Mat& image : drawn) {
    cv::Mat bgr = image.channels() == 1 ? cv::Mat() : image;
    if (image.channels() == 1) cv::cvtColor(image, bgr, cv::COLOR_GRAY2BGR);
    cv::Mat thumb;
    const double s = static_cast<double>(thumb_width) / bgr.cols;
    cv::resize(bgr, thumb, cv::Size(thumb_width, std::max(1, static_cast<int>(std::lround(bgr.rows * s)))), 0,
               0, cv::INTER_AREA);
    thumb_height = std::max(thumb_height, thumb.rows);
    thumbs.push_back(thumb);
  }
  const int rows = (static_cast<int>(thumbs.size()) + columns - 1) / columns;
  cv::Mat sheet(rows * thumb_height, columns * thumb_width, CV_8UC3, cv::Scalar(40, 40, 40));
  for (std::size_t i = 0; i < thumbs.size(); ++i) {
    const int r = static_cast<int>(i) / columns, c = static_cast<int>(i) % columns;
    thumbs[i].copyTo(sheet(cv::Rect(c * thumb_width, r * thumb_height, thumbs[i].cols, thumbs[i].rows)));
  }
  return sheet;
}

}  // namespace holo::calib
