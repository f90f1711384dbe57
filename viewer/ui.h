// The Dear ImGui panel of `femto view` (ui.cpp, the viewer's one C++ file): a HUD of the step's
// timings and counters, the sliders, the buttons and the debug-view toggles. The app fills a
// model each frame; the panel edits it and says what changed.
#pragma once

#include <femto/femto.h>

#include <stdbool.h>

#ifdef __cplusplus
extern "C"
{
#endif

	/// What the panel shows and edits.
	typedef struct fvUiModel
	{
		// Shown.
		double fps;                    ///< window frames a second
		double stepMs;                 ///< wall time of the last scene frame's steps
		bool overBudget;               ///< stepMs above the physics' share of a 60 Hz frame
		double stepShareMs;            ///< that share (FV_STEP_SHARE_MS)
		const float* stepHistory;      ///< ms of the last frames' steps, a ring (the profile graph)
		int historyCount, historyNext; ///< frames in it, and where the oldest is when full
		fmProfile profile;             ///< its stages
		fmStepStats stats;             ///< its counters
		long frames;                   ///< scene frames since the load or reset
		double simTime;                ///< s simulated
		bool paused;
		bool dragging;
		const char* status;      ///< the last problem, "" if none
		const char* description; ///< the scene's "description", "" if none
		const char* const* sceneNames;
		const int* sceneTopics;        ///< each scene's topic in topicNames, -1 none
		const char* const* topicNames; ///< the topics the list is grouped by, in its order
		int topicCount;
		int sceneCount;
		// Edited.
		int sceneIndex;
		int model;    ///< fmMaterialModel, linear to Mooney-Rivlin
		float youngs; ///< Pa
		float poisson;
		bool perParticle; ///< mass is kg per vertex, else kg/m^3
		float mass;
		float damping;
		float dt;
		int substeps;
		int integrator;     ///< fmIntegrator
		unsigned drawFlags; ///< fmDrawFlags
		// What the panel covers: its right edge in pixels (0 when collapsed), for framing.
		float panelRight;
		// What changed this frame.
		bool sceneChanged, materialChanged, bodiesChanged, timeChanged, integratorChanged;
		bool jump, pause, step, reset, frame;
	} fvUiModel;

	/// Set Dear ImGui up on the GLFW window @p glfwWindow (its callbacks chain to the window's).
	bool fvUi_Init(void* glfwWindow);

	/// Shut Dear ImGui down.
	void fvUi_Shutdown(void);

	/// Whether the panel has the mouse (a click there is not for the scene).
	bool fvUi_WantsMouse(void);

	/// Build and draw the panel over the current framebuffer; edits @p model.
	void fvUi_Frame(fvUiModel* model);

#ifdef __cplusplus
}
#endif
