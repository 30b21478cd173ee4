# The layering of everything outside engine/ (engine/layers.cmake has the engine's own): the
# libraries from the engine up to the executable, bottom to top. A folder may include only itself
# and the folders in its DEPS (and, through them, what those depend on); each DEPS entry must be
# listed before it. A file belongs to the longest folder of this list that holds it (app/gui/x.cpp
# to app/gui, app/cmd_run.cpp to app). tests/layering/check_frontend_layers.cmake (CTest
# frontend_layering) checks every #include "engine/...", "render/...", "haptics/...", "igtl/...",
# "python/..." and "app/..." in these folders against it; docs/architecture.md draws it.
set(PROSTATESIM_FRONTEND_LAYERS
  engine      # physics and scenarios (its own layers: engine/layers.cmake); includes nothing above
  render      # OpenGL 3.3 renderer, headless context, cameras; no GL provider linked
  haptics     # input devices and the haptic loop
  igtl        # OpenIGTLink server of run --igtl-port (poses, TRUS images out; tracked instruments in)
  python      # the prostatesim Python module (pybind11)
  app/plot    # 2D charts into an RGB buffer
  app/labelmap  # patient cases from a segmentation's label map (Teem, nifti2)
  app/checks  # validation cases against outside references, numerical stress cases
  app/core    # what the commands and the frontends share: the run / replay seams
  app/window  # the GLFW + Dear ImGui window the trainee window and the editor share
  app/frames  # headless replay frames (PNG writer thread, contact sheet)
  app/session # session capture and report (metrics.json, report.png, CSVs), drawn headless
  app/gui     # the trainee window (GLFW + Dear ImGui)
  app/editor  # the instructor's scenario editor: commands, and its window
  app         # the prostatesim executable: one file per subcommand
)
set(PROSTATESIM_FRONTEND_DEPS_engine)
set(PROSTATESIM_FRONTEND_DEPS_render engine)
set(PROSTATESIM_FRONTEND_DEPS_haptics engine)
set(PROSTATESIM_FRONTEND_DEPS_igtl haptics engine)
set(PROSTATESIM_FRONTEND_DEPS_python engine)
set(PROSTATESIM_FRONTEND_DEPS_app/plot engine)
set(PROSTATESIM_FRONTEND_DEPS_app/labelmap engine)
set(PROSTATESIM_FRONTEND_DEPS_app/checks engine)
set(PROSTATESIM_FRONTEND_DEPS_app/core haptics engine)
set(PROSTATESIM_FRONTEND_DEPS_app/window render)
set(PROSTATESIM_FRONTEND_DEPS_app/frames app/core app/plot render)
set(PROSTATESIM_FRONTEND_DEPS_app/session app/plot render)
set(PROSTATESIM_FRONTEND_DEPS_app/gui app/core app/window app/frames render haptics)
set(PROSTATESIM_FRONTEND_DEPS_app/editor app/window render)
set(PROSTATESIM_FRONTEND_DEPS_app app/core app/labelmap app/checks app/session app/plot app/window app/frames app/gui app/editor render haptics igtl)
