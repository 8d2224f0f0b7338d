#include "scene_interaction.h"

#include <vtkObjectFactory.h>
#include <vtkRenderWindowInteractor.h>

#include <cstdlib>

namespace clearway::ui::scene {
namespace {

// A press that moves less than this [px] before release is a click, not a drag.
constexpr int kClickSlopPx = 4;

}  // namespace

vtkStandardNewMacro(ConsoleInteractorStyle);

void ConsoleInteractorStyle::OnLeftButtonDown() {
  const int* position = GetInteractor()->GetEventPosition();
  press_[0] = position[0];
  press_[1] = position[1];
  vtkInteractorStyleTrackballCamera::OnLeftButtonDown();
}

void ConsoleInteractorStyle::OnLeftButtonUp() {
  vtkInteractorStyleTrackballCamera::OnLeftButtonUp();
  const int* position = GetInteractor()->GetEventPosition();
  if (std::abs(position[0] - press_[0]) + std::abs(position[1] - press_[1]) <= kClickSlopPx &&
      on_click)
    on_click(position[0], position[1]);
}

}  // namespace clearway::ui::scene
