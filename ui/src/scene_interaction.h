#pragma once

// The 3D view's mouse and keys: orbit (left drag), pan (middle drag or Shift + left drag), zoom
// (wheel), and a click (press and release without moving) handed to the view for picking. VTK's
// default key bindings ('3' stereo, 'w' wireframe, 'f' fly-to, 'p' pick, 'r' reset, 'e'/'q' exit,
// 's', 'u', 'j', 't') are all off: the console's own shortcuts (View menu) replace them.

#include <vtkInteractorStyleTrackballCamera.h>

#include <functional>

namespace clearway::ui::scene {

class ConsoleInteractorStyle : public vtkInteractorStyleTrackballCamera {
 public:
  static ConsoleInteractorStyle* New();

  // Called with the display position of a click.
  std::function<void(int x, int y)> on_click;

  void OnChar() override {}
  void OnKeyPress() override {}
  void OnKeyRelease() override {}
  void OnLeftButtonDown() override;
  void OnLeftButtonUp() override;

 private:
  int press_[2] = {0, 0};

 public:
  // Last: the macro takes no semicolon, and clang-format indents what follows it.
  vtkTypeMacro(ConsoleInteractorStyle, vtkInteractorStyleTrackballCamera)
};

}  // namespace clearway::ui::scene
