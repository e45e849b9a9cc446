// A saved project's version history, shared by the axis and machine views: one line per version,
// a Restore button on every version but the current one.

import { el } from "./dom.js";
import { api } from "./api.js";

export async function renderVersions(ol, project, restoreWith) {
  ol.replaceChildren();
  if (!project) return;
  let versions = [];
  try {
    versions = await api.get(`/api/projects/${project.id}/versions`);
  } catch (err) {
    return;
  }
  for (const v of versions) {
    const label = `v${v.version} · ${new Date(v.created * 1000).toLocaleString()}${v.note ? " · " + v.note : ""}`;
    const li = el("li", {}, el("span", { text: label }));
    if (v.version !== project.version) {
      const b = el("button", { type: "button", class: "small", text: "Restore", "aria-label": `Restore version ${v.version}` });
      b.addEventListener("click", () => restoreWith(api.post(`/api/projects/${project.id}/versions/${v.version}/restore`), `restored version ${v.version}`));
      li.append(" ", b);
    }
    ol.append(li);
  }
}
