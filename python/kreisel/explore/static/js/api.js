// The server's JSON API. A refused request throws an ApiError with the server's message and,
// for a checked parameter, the table and field it is about.

export class ApiError extends Error {
  constructor(message, table, field, status) {
    super(message);
    this.table = table;
    this.field = field;
    this.status = status;
  }
}

async function answer(response) {
  const type = response.headers.get('content-type') || '';
  if (!response.ok) {
    const body = type.includes('json') ? await response.json() : { error: await response.text() };
    throw new ApiError(body.error, body.table || null, body.field || null, response.status);
  }
  return response;
}

export async function getJSON(path) {
  return (await answer(await fetch(path))).json();
}

export async function postJSON(path, body) {
  const response = await fetch(path, {
    method: 'POST',
    headers: { 'content-type': 'application/json' },
    body: JSON.stringify(body),
  });
  return (await answer(response)).json();
}

// POSTs and saves the answer as a file, named as the server says.
export async function download(path, body) {
  const response = await answer(await fetch(path, {
    method: 'POST',
    headers: { 'content-type': 'application/json' },
    body: JSON.stringify(body),
  }));
  const disposition = response.headers.get('content-disposition') || '';
  const name = (disposition.match(/filename="([^"]+)"/) || [])[1] || 'kreisel-export';
  return saveBlob(await response.blob(), name);
}

// Saves a blob as a file (the browser's download); the last one saved is window.saved.
export function saveBlob(blob, name) {
  const url = URL.createObjectURL(blob);
  const a = document.createElement('a');
  a.href = url;
  a.download = name;
  document.body.appendChild(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 1000);
  window.saved = { name, blob };
  return name;
}
