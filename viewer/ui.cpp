// The Dear ImGui panel (ui.h). Dear ImGui is C++; the rest of the viewer is C.
#include "ui.h"

#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <GLFW/glfw3.h>

namespace
{
// The panel's width (pixels); its height fits its contents every frame.
const float FV_PANEL_WIDTH = 410.0f;

const char* const modelNames[] = {"linear", "corotated", "St. Venant-Kirchhoff", "Neo-Hookean",
                                  "Mooney-Rivlin"};

void showStats(const fvUiModel& m)
{
	ImGui::Text("%.0f fps   step %.2f ms%s", m.fps, m.stepMs, m.paused ? "   PAUSED" : "");
	if (m.overBudget)
	{
		// The physics' own time, not the whole frame's (software rendering is slow anyway).
		ImGui::SameLine();
		ImGui::TextColored(ImVec4(1.0f, 0.6f, 0.2f, 1.0f), "  over budget (%.1f ms of 16.7)",
		                   m.stepShareMs);
	}
	if (m.historyCount > 1)
	{
		// Box2D's profile: the step's time over the last seconds, the budget's share as the top.
		float top = (float)m.stepShareMs;
		for (int k = 0; k < m.historyCount; ++k)
			top = m.stepHistory[k] > top ? m.stepHistory[k] : top;
		ImGui::PlotLines("##profile", m.stepHistory, m.historyCount, m.historyNext,
		                 "step ms, last 5 s", 0.0f, top, ImVec2(FV_PANEL_WIDTH - 20.0f, 40.0f));
	}
	const fmProfile& p = m.profile;
	if (m.integrator == fm_explicit)
		ImGui::Text("forces %.2f  integrate %.2f  check %.2f ms", p.forces, p.integrate, p.check);
	else
		ImGui::Text("solve %.2f  finish %.2f  check %.2f ms", p.solve, p.finish, p.check);
	ImGui::Text("frame %ld  t = %.2f s  substeps %d", m.frames, m.simTime, m.stats.steps);
	if (m.integrator == fm_implicit)
		ImGui::Text("Newton %d  CG %d  residual %.2g", m.stats.newtonIterations,
		            m.stats.cgIterations, m.stats.residual);
	ImGui::Text("inverted tets %d  contacts %d", m.stats.invertedTets, m.stats.contacts);
	if (m.status != nullptr && m.status[0] != 0)
	{
		// Wrapped at the panel's edge, so the advice at the end of a failure shows; the panel's
		// height follows its contents (fvUi_Frame) instead of scrolling the controls away.
		ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.35f, 0.3f, 1.0f));
		ImGui::PushTextWrapPos(0.0f);
		ImGui::TextUnformatted(m.status);
		ImGui::PopTextWrapPos();
		ImGui::PopStyleColor();
	}
}

ImU32 strainColor(double strain)
{
	float rgb[3];
	fmDraw_StrainColor(strain, rgb);
	return ImGui::ColorConvertFloat4ToU32(ImVec4(rgb[0], rgb[1], rgb[2], 1.0f));
}

// The stress view's legend: the library's ramp (fmDraw_StrainColor) from 0 to
// FM_DRAW_FULL_STRAIN, with its ends and middle named.
void showStrainLegend()
{
	ImGui::TextUnformatted("equivalent strain sqrt(2 psi / E)");
	ImVec2 at = ImGui::GetCursorScreenPos();
	const float width = 300.0f, height = 12.0f;
	const int steps = 24;
	ImDrawList* draw = ImGui::GetWindowDrawList();
	for (int k = 0; k < steps; ++k)
	{
		double a = FM_DRAW_FULL_STRAIN * k / steps, b = FM_DRAW_FULL_STRAIN * (k + 1) / steps;
		float x0 = at.x + width * (float)k / steps, x1 = at.x + width * (float)(k + 1) / steps;
		draw->AddRectFilledMultiColor(ImVec2(x0, at.y), ImVec2(x1, at.y + height), strainColor(a),
		                              strainColor(b), strainColor(b), strainColor(a));
	}
	ImGui::Dummy(ImVec2(width, height));
	ImGui::Text("0");
	ImGui::SameLine(0.5f * width - 10.0f);
	ImGui::Text("%.2g", 0.5 * FM_DRAW_FULL_STRAIN);
	ImGui::SameLine(width - 40.0f);
	ImGui::Text("%.2g and more", FM_DRAW_FULL_STRAIN);
}

void showScene(fvUiModel& m)
{
	int index = m.sceneIndex;
	const char* current = index >= 0 && index < m.sceneCount ? m.sceneNames[index] : "";
	if (ImGui::BeginCombo("scene", current, ImGuiComboFlags_HeightLarge))
	{
		// Grouped by topic (the app sorts the list so): a header where the topic changes, the
		// built-in house first, on its own.
		for (int i = 0; i < m.sceneCount; ++i)
		{
			int topic = m.sceneTopics[i];
			if (i > 0 && (i == 1 || topic != m.sceneTopics[i - 1]))
				ImGui::TextDisabled("%s", topic >= 0 && topic < m.topicCount ? m.topicNames[topic]
				                                                             : "other");
			ImGui::Indent(i > 0 ? 8.0f : 0.0f);
			if (ImGui::Selectable(m.sceneNames[i], i == index) && i != index)
			{
				m.sceneIndex = i;
				m.sceneChanged = true;
			}
			ImGui::Unindent(i > 0 ? 8.0f : 0.0f);
		}
		ImGui::EndCombo();
	}
}

void showMaterial(fvUiModel& m)
{
	if (ImGui::Combo("model", &m.model, modelNames, 5))
		m.materialChanged = true;
	if (ImGui::SliderFloat("E (Pa)", &m.youngs, 1e3f, 1e8f, "%.3g", ImGuiSliderFlags_Logarithmic))
		m.materialChanged = true;
	if (ImGui::SliderFloat("nu", &m.poisson, -0.4f, 0.49f, "%.3f"))
		m.materialChanged = true;
	// Masses and damping re-create the bodies: applied when the slider is let go.
	if (m.perParticle)
		ImGui::SliderFloat("mass (kg/vertex)", &m.mass, 0.01f, 100.0f, "%.3g",
		                   ImGuiSliderFlags_Logarithmic);
	else
		ImGui::SliderFloat("density (kg/m3)", &m.mass, 1.0f, 20000.0f, "%.4g",
		                   ImGuiSliderFlags_Logarithmic);
	m.bodiesChanged |= ImGui::IsItemDeactivatedAfterEdit();
	ImGui::SliderFloat("damping /3ms", &m.damping, 0.95f, 1.0f, "%.4f");
	m.bodiesChanged |= ImGui::IsItemDeactivatedAfterEdit();
}

void showTime(fvUiModel& m)
{
	if (ImGui::SliderFloat("dt (s)", &m.dt, 1e-4f, 0.05f, "%.4g", ImGuiSliderFlags_Logarithmic))
		m.timeChanged = true;
	if (ImGui::SliderInt("substeps", &m.substeps, 1, 100))
		m.timeChanged = true;
	if (ImGui::RadioButton("explicit", &m.integrator, fm_explicit))
		m.integratorChanged = true;
	ImGui::SameLine();
	if (ImGui::RadioButton("implicit", &m.integrator, fm_implicit))
		m.integratorChanged = true;
}

void showButtons(fvUiModel& m)
{
	m.pause = ImGui::Button(m.paused ? "play (P)" : "pause (P)");
	ImGui::SameLine();
	m.step = ImGui::Button("step (S)");
	ImGui::SameLine();
	m.reset = ImGui::Button("reset (R)");
	ImGui::SameLine();
	m.jump = ImGui::Button("jump (space)");
	ImGui::SameLine();
	m.frame = ImGui::Button("frame (F)");
}

void showViews(fvUiModel& m)
{
	static const struct
	{
		const char* name;
		unsigned flag;
	} views[] = {{"surfaces", fm_drawSurfaces},   {"stress", fm_drawStress},
	             {"tets", fm_drawTetEdges},       {"inverted", fm_drawInvertedTets},
	             {"pins", fm_drawPins},           {"targets", fm_drawTargets},
	             {"floor", fm_drawFloor},         {"contacts", fm_drawContacts},
	             {"colliders", fm_drawColliders}, {"fibres", fm_drawFibres},
	             {"plastic", fm_drawPlastic},     {"damage", fm_drawDamage}};
	for (size_t i = 0; i < sizeof views / sizeof views[0]; ++i)
	{
		if (i % 4 != 0)
			ImGui::SameLine();
		ImGui::CheckboxFlags(views[i].name, &m.drawFlags, views[i].flag);
	}
	if (m.drawFlags & (fm_drawStress | fm_drawPlastic | fm_drawDamage))
		showStrainLegend();
}
} // namespace

extern "C" bool fvUi_Init(void* glfwWindow)
{
	IMGUI_CHECKVERSION();
	ImGui::CreateContext();
	ImGui::GetIO().IniFilename = nullptr; // no imgui.ini in the user's folder
	ImGui::StyleColorsDark();
	ImGuiStyle& style = ImGui::GetStyle();
	style.Alpha = 0.92f;
	// Slider handles thin and see-through: the value printed across the slider stays readable
	// wherever the handle is (a solid one covered the digits it sat on).
	style.GrabMinSize = 6.0f;
	style.Colors[ImGuiCol_SliderGrab].w = 0.45f;
	style.Colors[ImGuiCol_SliderGrabActive].w = 0.6f;
	return ImGui_ImplGlfw_InitForOpenGL(static_cast<GLFWwindow*>(glfwWindow), true) &&
	       ImGui_ImplOpenGL3_Init("#version 330 core");
}

extern "C" void fvUi_Shutdown(void)
{
	ImGui_ImplOpenGL3_Shutdown();
	ImGui_ImplGlfw_Shutdown();
	ImGui::DestroyContext();
}

extern "C" bool fvUi_WantsMouse(void)
{
	return ImGui::GetCurrentContext() != nullptr && ImGui::GetIO().WantCaptureMouse;
}

extern "C" void fvUi_Frame(fvUiModel* model)
{
	fvUiModel& m = *model;
	ImGui_ImplOpenGL3_NewFrame();
	ImGui_ImplGlfw_NewFrame();
	ImGui::NewFrame();
	ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
	ImGui::SetNextWindowSize(ImVec2(FV_PANEL_WIDTH, 0.0f), ImGuiCond_Always); // 0: fit the height
	ImGui::SetNextWindowCollapsed(false, ImGuiCond_FirstUseEver);
	ImGui::Begin("femto");
	m.panelRight =
	    ImGui::IsWindowCollapsed() ? 0.0f : ImGui::GetWindowPos().x + ImGui::GetWindowSize().x;
	showScene(m);
	if (m.description != nullptr && m.description[0] != 0)
	{
		ImGui::PushTextWrapPos(0.0f);
		ImGui::TextDisabled("%s", m.description);
		ImGui::PopTextWrapPos();
	}
	showStats(m);
	if (ImGui::CollapsingHeader("material and time", ImGuiTreeNodeFlags_DefaultOpen))
	{
		showMaterial(m);
		showTime(m);
	}
	showButtons(m);
	if (ImGui::CollapsingHeader("debug views", ImGuiTreeNodeFlags_DefaultOpen))
		showViews(m);
	if (ImGui::CollapsingHeader("controls"))
		ImGui::TextUnformatted("left drag on a body: pull it   left drag elsewhere: orbit\n"
		                       "right/middle drag: pan   wheel: zoom   F: frame\n"
		                       "space: jump   P: pause   S/N: step   R: reset\n"
		                       "I: integrator   M: next material model   Esc/Q: quit");
	ImGui::End();
	ImGui::Render();
	ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}
