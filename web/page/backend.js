// The web page's backend (docs/web.md): svetlo's WebAssembly module in a worker of its own
// (render_worker.js), and of it
//   - the `svetlo` object of the contract's "In the browser":
//       await svetlo.ready;
//       const {width, height, seconds, pixels} = await svetlo.render(SCENE, {engine, width,
//           height, spp, seed, threads, set});
//     SCENE is a bundled scene's name ("cornell.json"), a visitor's file put beside them by
//     svetlo.addFiles, or a scene object; pixels is a Float32Array of linear RGB, top row
//     first. A bad scene rejects with an Error whose message is the one-line error. An
//     `onPass(pass)` option is called with each pass of a progressive engine ({passes,
//     seconds, width, height, pixels}); svetlo.cancel() ends the render in progress after its
//     pass (a cross-origin isolated page: svetlo.canCancel), which then resolves with the
//     passes done and `cancelled` true;
//   - `svetloViewer`, which carries the viewer's requests (the page is svetlo serve's viewer,
//     apps/svetlo/viewer/, whose own backend.js says what it asks): each "/api/..." request
//     answered in the worker by the job layer's ViewerApi, as svetlo serve answers it.
// Requests and renders run one at a time in the worker, in order.
(function () {
    'use strict';
    const worker = new Worker(new URL('render_worker.js', document.currentScript.src));
    const waiting = new Map();  // id -> {resolve, reject}
    let nextId = 1;
    let info = {scenes: [], engines: [], cores: 1, memory: null, cancelAt: 0};
    let readyResolve, readyReject;
    const ready = new Promise((resolve, reject) => {
        readyResolve = resolve;
        readyReject = reject;
    });
    worker.onmessage = (event) => {
        const data = event.data;
        if (data.ready) {
            info = data;
            readyResolve();
            return;
        }
        if (data.failed !== undefined) {
            readyReject(new Error('svetlo: the WebAssembly module did not start: ' + data.failed));
            return;
        }
        const call = waiting.get(data.id);
        if (!call) return;
        if (data.pass !== undefined) {  // a pass of the render in progress
            if (call.onPass) call.onPass(data.pass);
            return;
        }
        if (data.chunk !== undefined) {  // bytes of a viewer's stream
            call.onChunk(data.chunk);
            return;
        }
        waiting.delete(data.id);
        if (data.response !== undefined) call.resolve(data.response);
        else if (data.error !== undefined) call.reject(new Error(data.error));
        else if (data.names !== undefined) call.resolve(data.names);
        else call.resolve({width: data.width, height: data.height, seconds: data.seconds,
                           passes: data.passes, cancelled: data.cancelled, pixels: data.pixels});
    };
    // The worker failed: the start, and every render waiting, end with its message.
    worker.onerror = (event) => {
        const error = new Error('svetlo: ' + event.message);
        readyReject(error);
        for (const call of waiting.values()) call.reject(error);
        waiting.clear();
    };

    /// Threads above one need a cross-origin isolated page (COOP and COEP headers).
    function threadsFor(asked) {
        if (!self.crossOriginIsolated) return 1;
        return asked === undefined || asked === null ? 0 : asked;
    }

    function render(scene, options) {
        return ready.then(() => new Promise((resolve, reject) => {
            const id = nextId++;
            const opts = Object.assign({}, options || {});
            const onPass = typeof opts.onPass === 'function' ? opts.onPass : null;
            delete opts.onPass;  // (a function does not cross to the worker)
            waiting.set(id, {resolve, reject, onPass});
            opts.threads = threadsFor(opts.threads);
            const isText = typeof scene !== 'string';
            worker.postMessage({id, scene: isText ? JSON.stringify(scene) : scene, isText,
                                options: opts, wantsPasses: onPass !== null});
        }));
    }

    /// The visitor's own files (File objects, or {name, bytes} with bytes an ArrayBuffer or a
    /// typed array), put beside the bundled scenes, each under its own name without folders
    /// (one of a bundled scene's name takes its place in this page): a scene or a model and
    /// the files it names (an OBJ's MTL and textures, a glTF's buffers). Resolves to the names
    /// given; svetlo.render('NAME') renders, and the viewer lists it.
    function addFiles(files) {
        return ready.then(() => Promise.all(Array.from(files, async (f) => {
            const bytes = f instanceof Blob ? await f.arrayBuffer() : f.bytes;
            const copy = bytes instanceof ArrayBuffer ? bytes.slice(0)
                : bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
            return {name: String(f.name), bytes: copy};
        }))).then((list) => new Promise((resolve, reject) => {
            const id = nextId++;
            waiting.set(id, {resolve, reject});
            worker.postMessage({id, files: list}, list.map((f) => f.bytes));
        }));
    }

    /// Ends the render in progress after its pass; false where the page cannot (its module
    /// has no memory shared with the page: not cross-origin isolated).
    function cancel() {
        if (!info.memory) return false;
        Atomics.store(new Int8Array(info.memory), info.cancelAt, 1);
        return true;
    }

    /// A viewer's request ("/api/render?..."), answered by the worker: {status, type,
    /// headers, body}; for a stream (/api/progressive) its bytes go to onChunk first.
    function request(target, onChunk) {
        return ready.then(() => new Promise((resolve, reject) => {
            const id = nextId++;
            waiting.set(id, {resolve, reject, onChunk});
            worker.postMessage(onChunk ? {id, stream: target} : {id, api: target});
        }));
    }

    /// The viewer's fetch: a Response as the browser's fetch would give it from svetlo serve.
    /// The progressive stream's Response comes with its first bytes, its body a stream fed as
    /// the passes come; init.signal's abort ends the render after its pass (svetlo.cancel).
    function viewerFetch(target, init) {
        const url = new URL(target, location.href);
        const path = url.pathname.slice(url.pathname.lastIndexOf('/api/'));
        const signal = init && init.signal;
        const answer = (r) => new Response(r.body,
                                           {status: r.status, headers: Object.assign(
                                               {'Content-Type': r.type}, r.headers)});
        if (!path.startsWith('/api/progressive')) return request(path + url.search).then(answer);
        return new Promise((resolve, reject) => {
            let body = null;
            const stream = new ReadableStream({start(c) { body = c; }});
            let started = false;
            const aborted = () => reject(new DOMException('aborted', 'AbortError'));
            if (signal) {
                if (signal.aborted) return aborted();
                signal.addEventListener('abort', () => {
                    cancel();
                    if (started) body.error(new DOMException('aborted', 'AbortError'));
                    else aborted();
                });
            }
            request(path + url.search, (chunk) => {
                if (!started) {
                    started = true;
                    resolve(new Response(stream, {status: 200}));
                }
                if (!(signal && signal.aborted)) body.enqueue(chunk);
            }).then((r) => {
                if (!started) return resolve(answer(r));
                if (!(signal && signal.aborted)) body.close();
            }, (e) => {
                if (started) body.error(e); else reject(e);
            });
        });
    }

    self.svetloViewer = {
        fetch: viewerFetch,
        ready,
        addFiles,
        get note() {
            return self.crossOriginIsolated
                ? `rendered in this page, on ${info.cores} threads`
                : 'rendered in this page on one thread: it is not cross-origin isolated (docs/web.md)';
        },
    };

    self.svetlo = {
        ready,
        render,
        addFiles,
        cancel,
        get canCancel() { return info.memory !== null; },
        get scenes() { return info.scenes.slice(); },
        get engines() { return info.engines.map((e) => e.name); },
        get threads() { return self.crossOriginIsolated ? info.cores : 1; },
    };
})();
