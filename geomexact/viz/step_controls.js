/* geomexact viewer: the trace panel's step controls, shared by the 2D and 3D pages (inlined
 * before each page's own script).  The slider always shows the absolute step number; the
 * op filter makes next / previous / play / the slider's arrow keys move only between the
 * steps of one operation; "go to step" jumps to a step number.  The operation of a step is
 * its label's text before "(" (labels are "op(arg, ...)", specs/viewer.md).
 *
 * window.geomexactStepControls(hooks) -> controls, with hooks.current() (the step shown)
 * and hooks.go(k) (show step k, 0..steps, and redraw); controls.load(labels) (one label per
 * step, step 1 first; an empty list hides nothing, the page hides the panel), stop(),
 * state() (for tests: filter, matching steps, message) and the stepping functions.
 */
(function () {
  "use strict";

  function byId(id) {
    return document.getElementById(id);
  }

  function count(value) {
    return value.toLocaleString("en-US");
  }

  function opOf(label) {
    const text = String(label);
    const open = text.indexOf("(");
    return open >= 0 ? text.slice(0, open) : text;
  }

  // the position in sorted `steps` of the first entry greater than `k`
  function firstAfter(steps, k) {
    let low = 0;
    let high = steps.length;
    while (low < high) {
      const middle = (low + high) >> 1;
      if (steps[middle] <= k) low = middle + 1;
      else high = middle;
    }
    return low;
  }

  window.geomexactStepControls = function (hooks) {
    const slider = byId("step");
    const goField = byId("step-go");
    const filter = byId("op-filter");
    const message = byId("step-message");
    const where = byId("filter-position");
    const play = byId("play");
    const speed = byId("speed");
    const controls = {
      steps: 0,
      ops: [],           // operation names, sorted
      stepsOf: {},       // op -> Uint32Array of its steps (1-based, increasing)
      chosen: "",        // "" = every step
      playing: false,
    };

    function say(text) {
      message.textContent = text || "";
      message.hidden = !text;
    }

    function matching() {
      return controls.chosen ? controls.stepsOf[controls.chosen] : null;
    }

    function showPosition() {
      const steps = matching();
      if (!steps) {
        where.textContent = "";
        return;
      }
      const k = hooks.current();
      const i = firstAfter(steps, k);
      const name = controls.chosen;
      if (i > 0 && steps[i - 1] === k) {
        where.textContent = name + " step " + count(i) + " of " + count(steps.length);
      } else {
        const next = i < steps.length ? "; next: step " + count(steps[i]) : "; none later";
        where.textContent = "not a " + name + " step (" + count(i) + " of " + count(steps.length) + " before it" + next + ")";
      }
    }

    function go(k) {
      hooks.go(Math.max(0, Math.min(controls.steps, k)));
      slider.value = String(hooks.current());
      showPosition();
    }

    // the step `n` steps (of the chosen op) after `k`, or k when there is none
    function after(k, n) {
      const steps = matching();
      if (!steps) return Math.min(controls.steps, k + n);
      const i = firstAfter(steps, k);
      if (i >= steps.length) return k;
      return steps[Math.min(steps.length - 1, i + n - 1)];
    }

    function before(k) {
      const steps = matching();
      if (!steps) return Math.max(0, k - 1);
      const i = firstAfter(steps, k - 1);  // the first step >= k
      return i > 0 ? steps[i - 1] : k;
    }

    controls.next = function () {
      const k = hooks.current();
      const target = after(k, 1);
      if (target === k) {
        say(controls.chosen ? "no " + controls.chosen + " step after step " + count(k) : "");
        return;
      }
      say("");
      go(target);
    };

    controls.previous = function () {
      const k = hooks.current();
      const target = before(k);
      if (target === k) {
        say(controls.chosen ? "no " + controls.chosen + " step before step " + count(k) : "");
        return;
      }
      say("");
      go(target);
    };

    controls.jump = function (text) {
      const cleaned = String(text).trim().replace(/[,_\s]/g, "");
      if (!/^[+-]?\d+$/.test(cleaned)) {
        say("“" + String(text).trim() + "” is not a step number: enter a whole number from 0 to " + count(controls.steps));
        return false;
      }
      const wanted = Number(cleaned);
      const target = Math.max(0, Math.min(controls.steps, wanted));
      controls.stop();
      go(target);
      if (target !== wanted) {
        say("step " + count(wanted) + " is outside 0.." + count(controls.steps) + ": showing step " + count(target));
      } else {
        say("");
      }
      return true;
    };

    controls.choose = function (op) {
      controls.chosen = op && controls.stepsOf[op] ? op : "";
      filter.value = controls.chosen;
      say("");
      showPosition();
    };

    controls.stop = function () {
      controls.playing = false;
      play.textContent = "▶ Play";
      play.setAttribute("aria-pressed", "false");
    };

    controls.togglePlay = function () {
      if (!controls.steps) return;
      if (controls.playing) {
        controls.stop();
        return;
      }
      if (after(hooks.current(), 1) === hooks.current()) go(0);
      say("");
      controls.playing = true;
      play.textContent = "❚❚ Pause";
      play.setAttribute("aria-pressed", "true");
      let clock = performance.now();
      let carry = 0;
      const tick = function (now) {
        if (!controls.playing) return;
        carry += ((now - clock) / 1000) * (parseFloat(speed.value) || 10);
        clock = now;
        const advance = Math.floor(carry);
        if (advance > 0) {
          carry -= advance;
          go(after(hooks.current(), advance));
        }
        if (after(hooks.current(), 1) === hooks.current()) {
          controls.stop();
          return;
        }
        requestAnimationFrame(tick);
      };
      requestAnimationFrame(tick);
    };

    controls.load = function (labels) {
      controls.stop();
      controls.steps = labels.length;
      const lists = {};
      for (let k = 1; k <= labels.length; k++) {
        const op = opOf(labels[k - 1]);
        (lists[op] || (lists[op] = [])).push(k);
      }
      controls.ops = Object.keys(lists).sort();
      controls.stepsOf = {};
      filter.replaceChildren();
      const all = document.createElement("option");
      all.value = "";
      all.textContent = "all (" + count(labels.length) + ")";
      filter.append(all);
      controls.ops.forEach(function (op) {
        controls.stepsOf[op] = Uint32Array.from(lists[op]);
        const option = document.createElement("option");
        option.value = op;
        option.textContent = op + " (" + count(lists[op].length) + ")";
        filter.append(option);
      });
      slider.max = String(controls.steps);
      slider.value = String(hooks.current());
      goField.max = String(controls.steps);
      controls.choose(controls.ops.indexOf(controls.chosen) >= 0 ? controls.chosen : "");
    };

    controls.state = function () {
      const steps = matching();
      return {
        filter: controls.chosen, ops: controls.ops.slice(), step: hooks.current(),
        matching: steps ? Array.from(steps) : null,
        message: message.hidden ? "" : message.textContent,
      };
    };

    controls.refresh = function () {
      slider.value = String(hooks.current());
      showPosition();
    };

    slider.addEventListener("input", function () {
      controls.stop();
      say("");
      go(parseInt(slider.value, 10));
    });
    slider.addEventListener("keydown", function (event) {
      const keys = { ArrowRight: controls.next, ArrowUp: controls.next, ArrowLeft: controls.previous, ArrowDown: controls.previous };
      if (!keys[event.key]) return;
      event.preventDefault();
      controls.stop();
      keys[event.key]();
    });
    goField.addEventListener("keydown", function (event) {
      if (event.key !== "Enter") return;
      event.preventDefault();
      controls.jump(goField.value);
    });
    byId("step-go-button").addEventListener("click", function () {
      controls.jump(goField.value);
    });
    filter.addEventListener("change", function () {
      controls.choose(filter.value);
    });
    play.addEventListener("click", controls.togglePlay);
    byId("first").addEventListener("click", function () {
      controls.stop();
      say("");
      go(0);
    });
    byId("last").addEventListener("click", function () {
      controls.stop();
      say("");
      go(controls.steps);
    });
    byId("previous").addEventListener("click", function () {
      controls.stop();
      controls.previous();
    });
    byId("next").addEventListener("click", function () {
      controls.stop();
      controls.next();
    });
    message.addEventListener("click", function () {
      say("");
    });
    return controls;
  };
})();
