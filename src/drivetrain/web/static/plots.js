// Plotly charts of a sizing: load motion, motor-shaft torque and speed, the speed-torque plane.
// Values arrive in SI; only display units are applied here (mm, deg, rpm).

const RPM = 60 / (2 * Math.PI);
const COLORS = ["#1f5fae", "#c2410c", "#15803d", "#7c3aed", "#b91c1c", "#0e7490", "#a16207"];
const CONFIG = { displaylogo: false, responsive: true, modeBarButtonsToRemove: ["lasso2d", "select2d", "autoScale2d"] };

function layout(title, extra = {}) {
  return {
    title: { text: title, font: { size: 13 }, x: 0.01, xanchor: "left" },
    margin: { l: 52, r: 52, t: 30, b: 36 },
    height: 230,
    font: { size: 11, family: "system-ui, sans-serif" },
    legend: { orientation: "h", x: 1, xanchor: "right", y: 1.0, yanchor: "bottom", font: { size: 10 }, bgcolor: "rgba(255,255,255,0.6)" },
    paper_bgcolor: "rgba(0,0,0,0)",
    plot_bgcolor: "#fff",
    ...extra,
  };
}

function ready() {
  return typeof window.Plotly !== "undefined";
}

function abs(values) {
  return values.map((v) => (v === null ? null : Math.abs(v)));
}

export function clear(node) {
  if (ready()) window.Plotly.purge(node);
  node.replaceChildren();
}

export function drawProfile(node, payload) {
  if (!ready()) return;
  const s = payload.series;
  const linear = payload.motion === "linear";
  const kx = linear ? 1000 : 180 / Math.PI;
  const pos = s.x.map((v) => (v === null ? null : v * kx));
  const speed = s.v.map((v) => (v === null ? null : linear ? v : v * RPM));
  const traces = [
    { x: s.t_s, y: pos, name: linear ? "position [mm]" : "angle [deg]", line: { color: COLORS[0] } },
    { x: s.t_s, y: speed, name: linear ? "speed [m/s]" : "speed [rpm]", yaxis: "y2", line: { color: COLORS[1] } },
  ];
  window.Plotly.react(node, traces, layout("Load motion", {
    xaxis: { title: { text: "time [s]" } },
    yaxis: { title: { text: linear ? "mm" : "deg" } },
    yaxis2: { title: { text: linear ? "m/s" : "rpm" }, overlaying: "y", side: "right", zeroline: false, tickmode: "auto", showgrid: false },
  }), CONFIG);
}

export function drawShaft(node, payload) {
  if (!ready()) return;
  const s = payload.series;
  const sel = payload.selected;
  const traces = [];
  if (sel && sel.series.torque_motor_Nm) {
    traces.push({ x: sel.series.t_s, y: sel.series.torque_motor_Nm, name: `torque, ${sel.motor}${sel.gearbox ? " + " + sel.gearbox : ""} [N m]`, line: { color: COLORS[0] } });
    traces.push({ x: sel.series.t_s, y: sel.series.omega_motor_rad_s.map((v) => (v === null ? null : v * RPM)), name: "speed [rpm]", yaxis: "y2", line: { color: COLORS[1] } });
  } else {
    if (s.torque_motor_Nm) traces.push({ x: s.t_s, y: s.torque_motor_Nm, name: "motor torque (with rotor) [N m]", line: { color: COLORS[0] } });
    traces.push({ x: s.t_s, y: s.torque_load_Nm, name: "load torque at the shaft [N m]", line: { color: COLORS[2], dash: s.torque_motor_Nm ? "dot" : "solid" } });
    traces.push({ x: s.t_s, y: s.omega_motor_rad_s.map((v) => (v === null ? null : v * RPM)), name: "speed [rpm]", yaxis: "y2", line: { color: COLORS[1] } });
  }
  window.Plotly.react(node, traces, layout("Motor shaft", {
    xaxis: { title: { text: "time [s]" } },
    yaxis: { title: { text: "N m" } },
    yaxis2: { title: { text: "rpm" }, overlaying: "y", side: "right", zeroline: false, tickmode: "auto", showgrid: false },
  }), CONFIG);
}

function envelopeTraces(env, color, width, compact = false) {
  const speed = env.speed_rad_s.map((w) => w * RPM);
  const tag = env.approximate ? " (derived)" : "";
  const who = env.rank ? `#${env.rank} ${env.name}` : env.name;
  return [
    { x: speed, y: env.continuous_Nm, name: compact ? `${who}${tag}` : `${who} continuous${tag}`, line: { color, width }, legendgroup: env.name },
    { x: speed, y: env.peak_Nm, name: `${who} peak${tag}`, line: { color, width, dash: "dash" }, legendgroup: env.name, showlegend: !compact },
  ];
}

// The speed-torque plane: operating points |n|, |T| of the cycle and the motor envelopes.
// ``picks`` (optional): compared candidates, each with its own cycle and envelope.
export function drawPlane(node, payload, picks = null) {
  if (!ready()) return;
  const traces = [];
  if (picks && picks.length) {
    picks.forEach((p, k) => {
      const color = COLORS[k % COLORS.length];
      traces.push({
        x: abs(p.series.omega_motor_rad_s).map((w) => (w === null ? null : w * RPM)), y: abs(p.series.torque_motor_Nm),
        mode: "lines", line: { width: 1.2, color }, name: `${p.motor}${p.gearbox ? " + " + p.gearbox : ""} cycle`, legendgroup: p.envelope.name,
      });
      traces.push(...envelopeTraces(p.envelope, color, 2));
    });
  } else {
    const s = payload.series;
    const sel = payload.selected;
    const omega = sel ? sel.series.omega_motor_rad_s : s.omega_motor_rad_s;
    const torque = sel ? sel.series.torque_motor_Nm : s.torque_motor_Nm || s.torque_load_Nm;
    const first = sel ? sel.envelope : payload.envelopes[0];
    traces.push({ x: abs(omega).map((w) => (w === null ? null : w * RPM)), y: abs(torque), mode: "lines", line: { width: 1.2, color: "#111" }, name: "cycle |n|, |T|" });
    const r = payload.result;
    const m = r.motor || (sel ? sel.motor_result : null);
    if (m && m.rms_torque_Nm !== undefined && (!sel || sel.ratio === 1)) {
      traces.push({ x: [r.mean_speed_rpm], y: [m.rms_torque_Nm], mode: "markers", marker: { size: 10, symbol: "diamond", color: COLORS[1] }, name: "RMS at mean speed" });
    }
    if (first) traces.push(...envelopeTraces(first, COLORS[0], 2.5));
    payload.envelopes.filter((e) => !first || e.name !== first.name).slice(0, 4).forEach((env, k) => {
      traces.push(...envelopeTraces(env, COLORS[(k + 2) % COLORS.length], 1, true).map((t) => ({ ...t, opacity: 0.5 })));
    });
  }
  window.Plotly.react(node, traces, layout("Speed-torque plane", {
    height: 330,
    xaxis: { title: { text: "motor speed |n| [rpm]" }, rangemode: "tozero" },
    yaxis: { title: { text: "|T| [N m]" }, rangemode: "tozero" },
    legend: { orientation: "v", x: 1.02, xanchor: "left", y: 1, yanchor: "top", font: { size: 10 } },
    margin: { l: 52, r: 10, t: 30, b: 40 },
  }), CONFIG);
}

export function drawEnvelope(node, env) {
  if (!ready()) return;
  window.Plotly.react(node, envelopeTraces(env, COLORS[0], 2.5), layout(`${env.name}${env.approximate ? " (derived from ratings)" : ""}`, {
    height: 290,
    legend: { orientation: "h", x: 0, xanchor: "left", y: -0.28, yanchor: "top", font: { size: 10 } },
    margin: { l: 52, r: 16, t: 30, b: 70 },
    xaxis: { title: { text: "speed [rpm]" }, rangemode: "tozero" },
    yaxis: { title: { text: "torque [N m]" }, rangemode: "tozero" },
  }), CONFIG);
}

// f1 of the drive train against the load position, the required f1 (2 x velocity bandwidth) dashed.
export function drawModes(node, modes) {
  if (!ready()) return;
  const x = modes.f1_by_position.map((r) => r.position_m * 1000);
  const f1 = modes.f1_by_position.map((r) => r.f1_Hz);
  const data = [{ x, y: f1, name: "f1", mode: "lines", line: { color: COLORS[0], width: 2 } }];
  const check = (modes.checks || [])[0];
  if (check && check.required !== null) data.push({ x: [x[0], x[x.length - 1]], y: [check.required, check.required], name: "required: 2 × velocity bandwidth", mode: "lines", line: { color: COLORS[4], dash: "dash" } });
  data.push({ x: [modes.worst_position_m * 1000], y: [modes.f1_min_Hz], name: `worst: ${modes.weakest_link}`, mode: "markers", marker: { color: COLORS[4], size: 9 } });
  window.Plotly.react(node, data, layout("First natural frequency across the stroke", {
    xaxis: { title: { text: "load position [mm]" } },
    yaxis: { title: { text: "f1 [Hz]" }, rangemode: "tozero" },
  }), CONFIG);
}
