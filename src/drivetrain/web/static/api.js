// Thin wrapper over fetch: JSON in and out; every error answer becomes an ApiError with the
// server's message ("detail"), the field at fault and the list of all errors.

export class ApiError extends Error {
  constructor(status, body) {
    const detail = (body && typeof body.detail === "string" && body.detail) || `request failed (${status})`;
    super(detail);
    this.status = status;
    this.field = body && body.field ? body.field : null;
    this.errors = body && Array.isArray(body.errors) ? body.errors : [{ field: this.field, message: detail }];
  }
}

async function parse(response) {
  const type = response.headers.get("content-type") || "";
  if (response.status === 204) return null;
  if (type.includes("application/json")) return response.json();
  return response.text();
}

// The server's anti-forgery token, written into the page: form and text bodies need it (another
// origin cannot read the page, so it cannot send it).
const TOKEN = document.querySelector('meta[name="drivetrain-token"]')?.content || "";

export async function request(method, url, body, { signal, raw = false } = {}) {
  const init = { method, headers: { "x-drivetrain-token": TOKEN }, signal };
  if (body instanceof FormData) {
    init.body = body;
  } else if (body !== undefined) {
    init.headers["content-type"] = "application/json";
    init.body = JSON.stringify(body);
  }
  const response = await fetch(url, init);
  if (!response.ok) {
    let payload = null;
    try {
      payload = await parse(response);
    } catch (e) {
      payload = null;
    }
    throw new ApiError(response.status, typeof payload === "object" ? payload : { detail: String(payload || "") });
  }
  if (raw) return response;
  return parse(response);
}

export const api = {
  get: (url, opts) => request("GET", url, undefined, opts),
  post: (url, body, opts) => request("POST", url, body, opts),
  put: (url, body, opts) => request("PUT", url, body, opts),
  patch: (url, body, opts) => request("PATCH", url, body, opts),
  del: (url, opts) => request("DELETE", url, undefined, opts),
};

// Save a Blob under a file name through a temporary link.
export function saveBlob(blob, filename) {
  const url = URL.createObjectURL(blob);
  const a = document.createElement("a");
  a.href = url;
  a.download = filename;
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 10000);
}

// The file name a response names in Content-Disposition, else the fallback.
export function filenameOf(response, fallback) {
  const header = response.headers.get("content-disposition") || "";
  const match = /filename="([^"]+)"/.exec(header);
  return match ? match[1] : fallback;
}
